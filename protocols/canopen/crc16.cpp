#include "protocols/canopen/crc16.hpp"

namespace mcemu::canopen {

std::uint16_t crc16_ccitt(std::span<const std::uint8_t> data, std::uint16_t crc) {
  for (std::uint8_t b : data) {
    crc = static_cast<std::uint16_t>(crc ^ (b << 8));
    for (int i = 0; i < 8; ++i) {
      crc = static_cast<std::uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
    }
  }
  return crc;
}

}  // namespace mcemu::canopen
