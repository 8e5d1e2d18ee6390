// Lexical rules of refgo.md §2.3, §4 and §9.1.
#include "protocols/refgo/codec.hpp"

#include <gtest/gtest.h>

namespace mcemu::refgo {
namespace {

TEST(Filter, TabBecomesSpaceControlsDroppedHighBytesKept) {
  EXPECT_EQ(filter_byte('\t'), ' ');
  for (int c = 0; c < 0x20; ++c) {
    if (c != '\t') {
      EXPECT_EQ(filter_byte(static_cast<unsigned char>(c)), -1) << c;
    }
  }
  EXPECT_EQ(filter_byte(0x7F), -1);
  EXPECT_EQ(filter_byte(' '), ' ');
  EXPECT_EQ(filter_byte('a'), 'a');
  EXPECT_EQ(filter_byte(0x80), 0x80);
  EXPECT_EQ(filter_byte(0xFF), 0xFF);
}

struct LexCase {
  std::string line;
  std::string echo;
  std::string word;
  std::string args;
  std::string trimmed;
  bool blank;
};

class LexTable : public ::testing::TestWithParam<LexCase> {};

TEST_P(LexTable, SplitsWordAndArguments) {
  const auto& c = GetParam();
  const Lexed l = lex(c.line);
  EXPECT_EQ(l.echo, c.echo);
  EXPECT_EQ(l.word(), c.word);
  EXPECT_EQ(l.args(), c.args);
  EXPECT_EQ(l.trimmed(), c.trimmed);
  EXPECT_EQ(l.blank(), c.blank);
}

INSTANTIATE_TEST_SUITE_P(
    Rules, LexTable,
    ::testing::Values(LexCase{"G-7200", "G-7200", "G", "-7200", "G-7200", false},
                      LexCase{"gw1000", "GW1000", "GW", "1000", "GW1000", false},
                      LexCase{"ACV100000", "ACV100000", "ACV", "100000", "ACV100000", false},
                      LexCase{"TPSR", "TPSR", "TPSR", "", "TPSR", false},
                      LexCase{"REF-19", "REF-19", "REF", "-19", "REF-19", false},
                      LexCase{"or3511,8", "OR3511,8", "OR", "3511,8", "OR3511,8", false},
                      LexCase{"  tp  ", "  TP  ", "TP", "  ", "TP", false},
                      LexCase{"OW 60fe,1,65536", "OW 60FE,1,65536", "OW", " 60FE,1,65536", "OW 60FE,1,65536", false},
                      LexCase{"123", "123", "", "123", "123", false}, LexCase{"?", "?", "", "?", "?", false},
                      LexCase{"\xFFTP", "\xFFTP", "", "\xFFTP", "\xFFTP", false},
                      LexCase{"TP\xFF", "TP\xFF", "TP", "\xFF", "TP\xFF", false},
                      LexCase{"t\xe4st", "T\xe4ST", "T", "\xe4ST", "T\xe4ST", false}, LexCase{"", "", "", "", "", true},
                      LexCase{"   ", "   ", "", "", "", true}));

struct IntCase {
  std::string args;
  ArgStatus status;
  std::int64_t value;
};

class IntTable : public ::testing::TestWithParam<IntCase> {};

TEST_P(IntTable, IntegerArgument) {
  const auto& c = GetParam();
  const IntArg a = parse_int_arg(c.args);
  EXPECT_EQ(a.status, c.status) << c.args;
  if (c.status == ArgStatus::ok) {
    EXPECT_EQ(a.value, c.value);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rules, IntTable,
    ::testing::Values(IntCase{"", ArgStatus::absent, 0}, IntCase{"   ", ArgStatus::absent, 0},
                      IntCase{"1000", ArgStatus::ok, 1000}, IntCase{"-7200", ArgStatus::ok, -7200},
                      IntCase{"+5", ArgStatus::ok, 5}, IntCase{"  42  ", ArgStatus::ok, 42},
                      IntCase{"0", ArgStatus::ok, 0}, IntCase{"9999999999", ArgStatus::ok, 9999999999},
                      IntCase{"-9999999999", ArgStatus::ok, -9999999999},
                      IntCase{"4294967296", ArgStatus::ok, 4294967296},
                      IntCase{"00000000001", ArgStatus::malformed, 0},  // 11 digits
                      IntCase{"10O0", ArgStatus::malformed, 0}, IntCase{"12X", ArgStatus::malformed, 0},
                      IntCase{"1.5", ArgStatus::malformed, 0}, IntCase{"- 5", ArgStatus::malformed, 0},
                      IntCase{"-", ArgStatus::malformed, 0}, IntCase{"+-1", ArgStatus::malformed, 0},
                      IntCase{"1 2", ArgStatus::malformed, 0}, IntCase{"\xFF", ArgStatus::malformed, 0},
                      IntCase{"0x10", ArgStatus::malformed, 0}));

TEST(Values, DecimalHexAndLimits) {
  EXPECT_EQ(parse_value("-10"), -10);
  EXPECT_EQ(parse_value("+10"), 10);
  EXPECT_EQ(parse_value("80H"), 0x80);
  EXPECT_EQ(parse_value("0X80"), 0x80);
  EXPECT_EQ(parse_value("10H"), 16);
  EXPECT_EQ(parse_value("FFFFFFFFH"), 0xFFFFFFFFLL);
  EXPECT_EQ(parse_value("9223372036854775807"), INT64_MAX);
  EXPECT_EQ(parse_value("-9223372036854775808"), INT64_MIN);
  EXPECT_EQ(parse_value("7FFFFFFFFFFFFFFFH"), INT64_MAX);
  EXPECT_EQ(parse_value("9223372036854775808"), std::nullopt);
  EXPECT_EQ(parse_value("-9223372036854775809"), std::nullopt);
  EXPECT_EQ(parse_value("8000000000000000H"), std::nullopt);
  EXPECT_EQ(parse_value("0X8000000000000000"), std::nullopt);
  EXPECT_EQ(parse_value("-80H"), std::nullopt);
  EXPECT_EQ(parse_value("-0X80"), std::nullopt);
  EXPECT_EQ(parse_value("X"), std::nullopt);
  EXPECT_EQ(parse_value("0X"), std::nullopt);
  EXPECT_EQ(parse_value("H"), std::nullopt);
  EXPECT_EQ(parse_value("ABC"), std::nullopt);
  EXPECT_EQ(parse_value(""), std::nullopt);
  EXPECT_EQ(parse_value("1 0"), std::nullopt);
}

TEST(ObjectArgs, ReadTokens) {
  auto r = parse_read_args("6041,0");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->index, 0x6041U);
  EXPECT_EQ(r->sub, 0U);
  EXPECT_FALSE(r->hex);
  EXPECT_EQ(r->prefix_len, 6U);

  r = parse_read_args("3410H,1H");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->index, 0x3410U);
  EXPECT_EQ(r->sub, 1U);
  EXPECT_EQ(r->prefix_len, 8U);

  r = parse_read_args(" 6041 , 0 , H  ");
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->hex);
  EXPECT_EQ(std::string_view(" 6041 , 0 , H  ").substr(0, r->prefix_len), " 6041 , 0");

  r = parse_read_args("3401,A");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->sub, 10U);

  r = parse_read_args("12345678,FFFFFFFF");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->index, 0x12345678U);
  EXPECT_EQ(r->sub, 0xFFFFFFFFU);

  for (const char* bad : {"", "6041", "6041,", ",0", "6041,0,", "6041,0,X", "6041,0,H,1", "123456789,0",
                          "6041,123456789", "60 41,0", "0X6041,0", "G041,0", "6041,0,HH", "6041H H,0"}) {
    EXPECT_FALSE(parse_read_args(bad)) << bad;
  }
}

TEST(ObjectArgs, WriteTokens) {
  auto w = parse_write_args("6091,1,1");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->index, 0x6091U);
  EXPECT_EQ(w->sub, 1U);
  EXPECT_EQ(w->value, 1);
  EXPECT_EQ(w->prefix_len, 8U);

  w = parse_write_args(" 60FE,1,65536  ");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->prefix_len, 13U);

  w = parse_write_args("607C,0,-10");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->value, -10);

  w = parse_write_args("6040,0,0X0F");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->value, 15);

  for (const char* bad : {"", "6040,0", "6040,0,", "6040,0,X", "6040,0,1,2", "6040,,1", "6040,0,-1H", "6040,0,1.5"}) {
    EXPECT_FALSE(parse_write_args(bad)) << bad;
  }
}

}  // namespace
}  // namespace mcemu::refgo
