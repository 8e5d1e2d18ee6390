#include "protocols/faulhaber/crc.hpp"

#include <array>

namespace mcemu::faulhaber {

namespace {

// The bitwise routine of §3 run once per byte value: the table form gives the same result.
constexpr std::array<std::uint8_t, 256> make_table() {
  std::array<std::uint8_t, 256> t{};
  for (unsigned v = 0; v < 256; ++v) {
    auto c = static_cast<std::uint8_t>(v);
    for (int bit = 0; bit < 8; ++bit) {
      c = (c & 0x01) ? static_cast<std::uint8_t>((c >> 1) ^ 0xD5) : static_cast<std::uint8_t>(c >> 1);
    }
    t[v] = c;
  }
  return t;
}

constexpr auto k_table = make_table();

}  // namespace

std::uint8_t crc8_update(std::uint8_t crc, std::span<const std::uint8_t> bytes) {
  for (const std::uint8_t b : bytes) crc = k_table[static_cast<std::uint8_t>(crc ^ b)];
  return crc;
}

}  // namespace mcemu::faulhaber
