// Byte helpers for SDO frames (CiA 301 §7.2.4): the command byte + index/sub header and
// little-endian 32-bit fields. Shared by the segmented and the block parts of the SDO server.
#pragma once

#include <cstddef>
#include <cstdint>

#include "protocols/canopen/types.hpp"

namespace mcemu::canopen::sdo_frames {

inline Payload header(std::uint8_t b0, std::uint16_t index, std::uint8_t sub) {
  Payload p{};
  p[0] = b0;
  p[1] = static_cast<std::uint8_t>(index & 0xFF);
  p[2] = static_cast<std::uint8_t>(index >> 8);
  p[3] = sub;
  return p;
}

inline void put_u32(Payload& p, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) p[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

inline std::uint32_t get_u32(const Payload& p, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[at + i]) << (8 * i);
  return v;
}

}  // namespace mcemu::canopen::sdo_frames
