#include "protocols/slcan/codec.hpp"

#include <gtest/gtest.h>

namespace mcemu::slcan {
namespace {

struct ParseCase {
  std::string line;
  std::optional<ParseError> error;  // nullopt = accepted
  CommandKind kind = CommandKind::empty;
};

class Parse : public ::testing::TestWithParam<ParseCase> {};

TEST_P(Parse, Classifies) {
  const auto& c = GetParam();
  const ParseResult r = parse_line(c.line);
  if (c.error) {
    ASSERT_TRUE(std::holds_alternative<ParseError>(r)) << c.line;
    EXPECT_EQ(std::get<ParseError>(r), *c.error) << c.line;
  } else {
    ASSERT_TRUE(std::holds_alternative<Command>(r)) << c.line << ": " << to_string(std::get<ParseError>(r));
    EXPECT_EQ(std::get<Command>(r).kind, c.kind) << c.line;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Lawicel, Parse,
    ::testing::Values(
        ParseCase{"", std::nullopt, CommandKind::empty}, ParseCase{"O", std::nullopt, CommandKind::open},
        ParseCase{"L", std::nullopt, CommandKind::listen}, ParseCase{"C", std::nullopt, CommandKind::close},
        ParseCase{"S0", std::nullopt, CommandKind::bitrate}, ParseCase{"S9", std::nullopt, CommandKind::bitrate},
        ParseCase{"s031C", std::nullopt, CommandKind::btr}, ParseCase{"V", std::nullopt, CommandKind::version},
        ParseCase{"v", std::nullopt, CommandKind::version_lower}, ParseCase{"N", std::nullopt, CommandKind::serial},
        ParseCase{"F", std::nullopt, CommandKind::flags}, ParseCase{"Z0", std::nullopt, CommandKind::timestamps},
        ParseCase{"Z1", std::nullopt, CommandKind::timestamps},
        ParseCase{"M00000000", std::nullopt, CommandKind::acceptance_code},
        ParseCase{"mFFFFFFFF", std::nullopt, CommandKind::acceptance_mask},
        ParseCase{"W2", std::nullopt, CommandKind::setting}, ParseCase{"X1", std::nullopt, CommandKind::setting},
        ParseCase{"Q2", std::nullopt, CommandKind::setting}, ParseCase{"U6", std::nullopt, CommandKind::setting},
        ParseCase{"t0800", std::nullopt, CommandKind::frame},
        ParseCase{"t63284041600000000000", std::nullopt, CommandKind::frame},
        ParseCase{"T12ABCDEF2AA55", std::nullopt, CommandKind::frame},
        ParseCase{"r7321", std::nullopt, CommandKind::frame}, ParseCase{"R1FFFFFFF0", std::nullopt, CommandKind::frame},
        ParseCase{"t7FF0", std::nullopt, CommandKind::frame},
        // errors (§3.4 "anything else", §3.5 validation order)
        ParseCase{"K", ParseError::unknown_command}, ParseCase{"O1", ParseError::unknown_command},
        ParseCase{"V0", ParseError::unknown_command}, ParseCase{"F00", ParseError::unknown_command},
        ParseCase{"S10", ParseError::bad_argument}, ParseCase{"S", ParseError::bad_argument},
        ParseCase{"s31C", ParseError::bad_argument}, ParseCase{"M0000", ParseError::bad_argument},
        ParseCase{"sXYZW", ParseError::bad_argument}, ParseCase{"Z2", ParseError::bad_argument},
        ParseCase{"W3", ParseError::bad_argument}, ParseCase{"X2", ParseError::bad_argument},
        ParseCase{"U7", ParseError::bad_argument}, ParseCase{"P", ParseError::unknown_command},
        ParseCase{"A", ParseError::unknown_command}, ParseCase{"d1230", ParseError::unknown_command},
        ParseCase{"D1230", ParseError::unknown_command}, ParseCase{"b1230", ParseError::unknown_command},
        ParseCase{"B1230", ParseError::unknown_command}, ParseCase{"x1230", ParseError::unknown_command},
        ParseCase{"z", ParseError::unknown_command}, ParseCase{"Y", ParseError::unknown_command},
        ParseCase{"y", ParseError::unknown_command}, ParseCase{"1", ParseError::unknown_command},
        ParseCase{"t63G0", ParseError::bad_hex}, ParseCase{"t63290000000000000000", ParseError::bad_dlc},
        ParseCase{"t632F", ParseError::bad_dlc}, ParseCase{"t6328404160", ParseError::bad_length},
        ParseCase{"t080000", ParseError::bad_length}, ParseCase{"t8000", ParseError::id_range},
        ParseCase{"T200000000", ParseError::id_range}, ParseCase{"r732100", ParseError::bad_length},
        ParseCase{"t 0800", ParseError::non_printable}, ParseCase{"t08", ParseError::bad_length},
        ParseCase{"t", ParseError::bad_length}, ParseCase{"t0811G0", ParseError::bad_hex},
        ParseCase{"t0800\x80", ParseError::non_printable}, ParseCase{"r7329", ParseError::bad_dlc},
        ParseCase{"t08000011", ParseError::bad_length}));

TEST(Parse, FrameFields) {
  const auto r = parse_line("t6328407a600000000000");
  const auto& f = std::get<Command>(r).frame;
  EXPECT_EQ(f.id, 0x632u);
  EXPECT_FALSE(f.extended);
  EXPECT_FALSE(f.rtr);
  EXPECT_EQ(f.dlc, 8);
  EXPECT_EQ(f.data[0], 0x40);
  EXPECT_EQ(f.data[1], 0x7A);
  EXPECT_EQ(f.data[2], 0x60);
  const auto e = std::get<Command>(parse_line("T12ABCDEF2AA55")).frame;
  EXPECT_EQ(e.id, 0x12ABCDEFu);
  EXPECT_TRUE(e.extended);
  EXPECT_EQ(e.dlc, 2);
  EXPECT_EQ(e.data[0], 0xAA);
  EXPECT_EQ(e.data[1], 0x55);
  const auto r3 = std::get<Command>(parse_line("r7321")).frame;
  EXPECT_TRUE(r3.rtr);
  EXPECT_EQ(r3.dlc, 1);
  EXPECT_EQ(std::get<Command>(parse_line("S4")).arg, 4u);
  EXPECT_EQ(std::get<Command>(parse_line("s031c")).arg, 0x031Cu);
}

TEST(Encode, ExactDigitsUpperCase) {
  can::Frame f{0x5B2, false, false, 8, {0x4B, 0x41, 0x60, 0x00, 0x40, 0x00, 0x00, 0x00}};
  EXPECT_EQ(encode_frame(f), "t5B284B41600040000000\r");
  can::Frame hb{0x732, false, false, 1, {0x7F}};
  EXPECT_EQ(encode_frame(hb), "t73217F\r");
  EXPECT_EQ(encode_frame(hb, std::chrono::milliseconds(6703)), "t73217F1A2F\r");
  EXPECT_EQ(encode_frame(hb, std::chrono::milliseconds(60000 + 6703)), "t73217F1A2F\r");
  EXPECT_EQ(encode_frame(hb, std::chrono::milliseconds(59999)), "t73217FEA5F\r");
  can::Frame empty{0x080, false, false, 0, {0xAA}};  // bytes beyond the DLC never leak
  EXPECT_EQ(encode_frame(empty), "t0800\r");
  can::Frame bad_dlc{0x123, false, false, 12, {1, 2, 3, 4, 5, 6, 7, 8}};
  EXPECT_EQ(encode_frame(bad_dlc), "t12380102030405060708\r");
  EXPECT_EQ(encode_frame(can::Frame{0x12ABCDEF, true, false, 1, {0xab}}), "T12ABCDEF1AB\r");
  EXPECT_EQ(encode_frame(can::Frame{0x3B2, false, true, 6, {}}), "r3B26\r");
  EXPECT_EQ(encode_frame(can::Frame{0x1, true, true, 0, {}}), "R000000010\r");
}

TEST(Encode, RoundTripsThroughParse) {
  for (std::uint8_t dlc = 0; dlc <= 8; ++dlc) {
    can::Frame f{0x7A5, false, false, dlc, {0xDE, 0xAD, 0xBE, 0xEF, 0x01, 0x23, 0x45, 0x67}};
    for (std::uint8_t i = dlc; i < 8; ++i) f.data[i] = 0;
    std::string line = encode_frame(f);
    ASSERT_EQ(line.back(), '\r');
    line.pop_back();
    EXPECT_EQ(line.size(), 5u + 2u * dlc);
    const auto r = parse_line(line);
    ASSERT_TRUE(std::holds_alternative<Command>(r));
    EXPECT_EQ(std::get<Command>(r).frame, f);
  }
}

}  // namespace
}  // namespace mcemu::slcan
