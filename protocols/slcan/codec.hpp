// SLCAN (Lawicel ASCII) line codec: one input line → one command, and a CAN frame → one output
// line (slcan-canopen.md §3.4–§3.6). Pure and stateless; the session applies the commands.
//
// Contract: parse_line() never throws; anything it does not accept is a ParseError, which the
// session answers with BEL. encode_frame() derives the number of data digits from frame.dlc only
// (clamped to 8), always upper-case hex, CR only.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "protocols/can/frame.hpp"

namespace mcemu::slcan {

enum class CommandKind : std::uint8_t {
  empty,            // ""                → \r
  open,             // O
  listen,           // L
  close,            // C
  bitrate,          // S0…S9
  btr,              // shhhh
  version,          // V
  version_lower,    // v
  serial,           // N
  flags,            // F
  timestamps,       // Z0 / Z1
  acceptance_code,  // Mhhhhhhhh
  acceptance_mask,  // mhhhhhhhh
  setting,          // W0–2, X0–1, Q0–2, U0–6 (remembered, no effect)
  frame,            // t, T, r, R
};

struct Command {
  CommandKind kind = CommandKind::empty;
  char letter = 0;        // the command letter as sent
  std::uint32_t arg = 0;  // digit or hex parameter of S, s, M, m, W, X, Q, U, Z
  can::Frame frame;       // kind == frame
};

// Why a line is answered with BEL (also the trace reason of §11.2).
enum class ParseError : std::uint8_t {
  overlong,         // more than 64 bytes before the line end
  non_printable,    // a byte outside 0x21…0x7E
  unknown_command,  // letter not in the table, or extra characters after a command
  bad_argument,     // parameter with wrong digit count or out of range
  bad_dlc,          // DLC not 0…8
  bad_length,       // line length does not match the DLC
  bad_hex,          // non-hex digit in identifier or data
  id_range,         // identifier above 7FF / 1FFFFFFF
};

using ParseResult = std::variant<Command, ParseError>;

// Parses one line without its terminator. Does not check the session state (§3.5 step 5).
ParseResult parse_line(std::string_view line);

std::string_view to_string(ParseError e);

// `t`/`T`/`r`/`R` line for the frame, with a 4-digit timestamp (ms modulo 60000) when given, and CR.
std::string encode_frame(const can::Frame& frame, std::optional<std::chrono::milliseconds> timestamp = std::nullopt);

}  // namespace mcemu::slcan
