// CRC-8 of faulhaber.md §3: the RS232 capture's two vectors, the catalogue check value and the
// third-party reference frames (CRC over bytes 1 … L−1).
#include "protocols/faulhaber/crc.hpp"

#include <gtest/gtest.h>

#include <string_view>

#include "tests/protocols/faulhaber/spec_frames.hpp"
#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

struct Vector {
  const char* name;
  std::string_view covered;
  std::uint8_t crc;
};

const Vector k_vectors[] = {
    {"RS232 SDO write request", "09 01 02 40 60 00 06 00", 0x2C},
    {"RS232 SDO write response", "07 01 02 40 60 00", 0xDB},
    {"read 6064h", "07 01 01 64 60 00", 0x56},
    {"6064h = 9", "0B 01 01 64 60 00 09 00 00 00", 0x53},
    {"read 6041h", "07 01 01 41 60 00", 0x73},
    {"6041h = 0x0440", "09 01 01 41 60 00 40 04", 0x6C},
    {"empty", "", 0xFF},
};

TEST(Crc8, Vectors) {
  for (const auto& v : k_vectors) {
    EXPECT_EQ(crc8(test::bytes(v.covered)), v.crc) << v.name;
  }
}

TEST(Crc8, CheckValue) {
  const std::string_view text = "123456789";
  EXPECT_EQ(crc8(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())), 0x64);
}

TEST(Crc8, UpdateContinuesOverPieces) {
  const auto b = test::bytes("0B 01 01 64 60 00 09 00 00 00");
  for (std::size_t cut = 0; cut <= b.size(); ++cut) {
    const std::span<const std::uint8_t> all(b);
    EXPECT_EQ(crc8_update(crc8(all.first(cut)), all.subspan(cut)), 0x53) << "cut at " << cut;
  }
}

// The routine exactly as §3 words it, bit by bit, against the library for every single byte and
// every pair of bytes.
std::uint8_t bitwise(std::span<const std::uint8_t> b) {
  std::uint8_t crc = 0xFF;
  for (const auto x : b) {
    crc ^= x;
    for (int i = 0; i < 8; ++i) crc = (crc & 1) ? static_cast<std::uint8_t>((crc >> 1) ^ 0xD5) : crc >> 1;
  }
  return crc;
}

TEST(Crc8, MatchesTheBitwiseRoutine) {
  for (unsigned a = 0; a < 256; ++a) {
    for (unsigned b = 0; b < 256; b += 17) {
      const std::uint8_t two[2] = {static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b)};
      ASSERT_EQ(crc8(two), bitwise(two)) << a << "," << b;
    }
  }
}

TEST(Crc8, EverySpecFrameCarriesItsCrc) {
  for (const auto& f : test::k_spec_frames) {
    const auto b = test::bytes(f.hex);
    ASSERT_GE(b.size(), 6u) << f.name;
    EXPECT_EQ(crc8(std::span<const std::uint8_t>(b).subspan(1, b[1] - 1)), b[b[1]]) << f.name;
  }
}

}  // namespace
}  // namespace mcemu::faulhaber
