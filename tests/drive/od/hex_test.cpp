#include "drive/od/hex.hpp"

#include <gtest/gtest.h>

namespace mcemu::od {
namespace {

TEST(Hex, DigitsAndLimits) {
  EXPECT_EQ(hex_digit('0'), 0);
  EXPECT_EQ(hex_digit('f'), 15);
  EXPECT_EQ(hex_digit('F'), 15);
  EXPECT_EQ(hex_digit('g'), -1);
  EXPECT_EQ(parse_hex("6041", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex("00000000000000ff", 0xFF), 0xFFu) << "leading zeros do not count against the limit";
  EXPECT_EQ(parse_hex("FFFFFFFFFFFFFFFF", ~std::uint64_t{0}), ~std::uint64_t{0});
  EXPECT_FALSE(parse_hex("10000000000000000", ~std::uint64_t{0})) << "overflow";
  EXPECT_FALSE(parse_hex("100", 0xFF));
  EXPECT_FALSE(parse_hex("", 0xFF));
  EXPECT_FALSE(parse_hex("0x10", 0xFF)) << "no prefix";
  EXPECT_FALSE(parse_hex("10h", 0xFF)) << "no suffix";
  EXPECT_FALSE(parse_hex(" 1", 0xFF));
}

}  // namespace
}  // namespace mcemu::od
