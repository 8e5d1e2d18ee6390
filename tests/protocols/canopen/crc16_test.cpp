#include "protocols/canopen/crc16.hpp"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace mcemu::canopen {
namespace {

std::uint16_t crc(std::string_view s) {
  std::vector<std::uint8_t> v(s.begin(), s.end());
  return crc16_ccitt(v);
}

TEST(Crc16, CheckValuesOfTheSpec) {  // slcan-canopen.md §6.6
  EXPECT_EQ(crc("123456789"), 0x31C3);
  EXPECT_EQ(crc("MC349_ETH_RE"), 0xA34D);
  const std::vector<std::uint8_t> target{0x30, 0x75, 0x00, 0x00};
  EXPECT_EQ(crc16_ccitt(target), 0x1F11);
  EXPECT_EQ(crc16_ccitt({}), 0x0000);
}

TEST(Crc16, IncrementalEqualsWhole) {
  const std::string_view s = "123456789";
  std::vector<std::uint8_t> a(s.begin(), s.begin() + 4), b(s.begin() + 4, s.end());
  EXPECT_EQ(crc16_ccitt(b, crc16_ccitt(a)), 0x31C3);
}

}  // namespace
}  // namespace mcemu::canopen
