// Trace text of frames (issue 24 item 4): the wire bytes as hex and a one-line summary such as
// `SDO read 6041.00 → 0x0427`, `SDO write 6040.00 = 0x000F`, `statusword 0x0427`,
// `EMCY 3210h reg 05 word 0004`, `boot "MC 5005"`, `error 1234.00 0x06020000`. Codes 0x00 and
// 0x03 mean different things in the two directions, hence the direction argument. Pure.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "protocols/faulhaber/frame.hpp"

namespace mcemu::faulhaber {

enum class Direction : std::uint8_t { to_drive, to_host };

// "53 07 01 01 41 60 00 73 45" (upper case, one space between bytes).
std::string hex(std::span<const std::uint8_t> bytes);
std::string describe(const FrameView& f, Direction dir);

// The same, appended to `out` (a reused buffer: no allocation once it has grown).
void append_hex(std::string& out, std::span<const std::uint8_t> bytes);
void append_description(std::string& out, const FrameView& f, Direction dir);
// Appends `digits` upper-case hex digits of v.
void append_hex(std::string& out, std::uint32_t v, int digits);

}  // namespace mcemu::faulhaber
