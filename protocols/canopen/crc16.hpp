// CRC-16-CCITT of SDO block transfers (slcan-canopen.md §6.6): polynomial 0x1021, initial value 0,
// MSB first, no reflection, no final XOR ("XMODEM"). Pure.
#pragma once

#include <cstdint>
#include <span>

namespace mcemu::canopen {

std::uint16_t crc16_ccitt(std::span<const std::uint8_t> data, std::uint16_t crc = 0);

}  // namespace mcemu::canopen
