// CRC-8 of the FAULHABER MC V3.0 binary RS232 protocol (faulhaber.md §3): initial value 0xFF, each
// byte XORed in, then 8 times "shift right, XOR 0xD5 if bit 0 was set"; no final XOR. In catalogue
// terms: width 8, polynomial 0xAB (0xD5 reflected), reflected in and out, check value 0x64.
// A frame's CRC covers its bytes 1 … L−1 (length byte through the last data byte). Pure.
#pragma once

#include <cstdint>
#include <span>

namespace mcemu::faulhaber {

inline constexpr std::uint8_t k_crc_initial = 0xFF;

// Continues a CRC over more bytes (start with k_crc_initial).
std::uint8_t crc8_update(std::uint8_t crc, std::span<const std::uint8_t> bytes);
inline std::uint8_t crc8(std::span<const std::uint8_t> bytes) { return crc8_update(k_crc_initial, bytes); }

}  // namespace mcemu::faulhaber
