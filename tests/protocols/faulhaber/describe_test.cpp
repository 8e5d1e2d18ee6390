// Trace summaries of frames in both directions (issue 24 item 4).
#include "protocols/faulhaber/describe.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

struct SummaryCase {
  std::string_view hex;
  Direction dir;
  const char* summary;
};

const SummaryCase k_cases[] = {
    {"53 07 01 01 41 60 00 73 45", Direction::to_drive, "SDO read 6041.00"},
    {"53 09 01 01 41 60 00 27 04 F4 45", Direction::to_host, "SDO read 6041.00 → 0x0427"},
    {"53 0B 01 01 05 30 09 FF FF FF FF 9D 45", Direction::to_host, "SDO read 3005.09 → 0xFFFFFFFF"},
    {"53 0B 01 02 FF 60 00 64 00 00 00 59 45", Direction::to_drive, "SDO write 60FF.00 = 0x00000064"},
    {"53 09 01 02 40 60 00 0F 00 25 45", Direction::to_drive, "SDO write 6040.00 = 0x000F"},
    {"53 08 01 02 60 60 00 03 A2 45", Direction::to_drive, "SDO write 6060.00 = 0x03"},
    {"53 07 01 02 40 60 00 DB 45", Direction::to_host, "SDO write 6040.00 ok"},
    {"53 0B 01 03 34 12 00 00 00 02 06 2B 45", Direction::to_host, "error 1234.00 0x06020000"},
    {"53 07 01 03 34 12 00 DC 45", Direction::to_host, "abort 1234.00 acknowledged"},
    {"53 06 01 05 27 04 21 45", Direction::to_host, "statusword 0x0427"},
    {"53 0C 01 07 10 32 05 04 00 00 00 00 83 45", Direction::to_host, "EMCY 3210h reg 05 word 0004"},
    {"53 0B 01 00 4D 43 20 35 30 30 35 8E 45", Direction::to_host, "boot \"MC 5005\""},
    {"53 04 01 00 50 45", Direction::to_drive, "reset node"},
    {"53 06 01 00 00 00 00 45", Direction::to_drive, "reset node (2 data bytes ignored)"},
    {"53 06 01 04 0F 00 59 45", Direction::to_drive, "controlword 0x000F"},
    {"53 05 01 04 00 55 45", Direction::to_host, "controlword ok"},
    {"53 05 01 04 01 00 45", Direction::to_host, "controlword refused (error 1)"},
    {"53 0B 01 03 34 12 00 00 00 00 08 00 45", Direction::to_drive, "abort request 1234.00 0x08000000"},
    {"53 07 01 06 41 60 00 00 45", Direction::to_drive, "command 0x06 (3 data bytes)"},
    {"53 05 01 01 41 00 45", Direction::to_drive, "command 0x01 (1 data bytes)"},
    {"53 0A 01 01 08 10 00 4D 43 53 00 45", Direction::to_host, "SDO read 1008.00 → \"MCS\""},
    {"53 0A 01 01 08 10 00 00 01 02 00 45", Direction::to_host, "SDO read 1008.00 → [00 01 02]"},
    {"53 07 01 02 40 60 00 00 45", Direction::to_drive, "SDO write 6040.00 (no value)"},
};

TEST(Describe, Summaries) {
  for (const auto& c : k_cases) {
    const auto d = decode(test::bytes(c.hex), false);
    ASSERT_EQ(d.error, DecodeError::none) << c.hex;
    EXPECT_EQ(describe(d.frame.view(), c.dir), c.summary) << c.hex;
  }
}

TEST(Describe, Hex) {
  EXPECT_EQ(hex(test::bytes("53 07 0a ff")), "53 07 0A FF");
  EXPECT_EQ(hex(test::bytes("00")), "00");
  EXPECT_EQ(hex({}), "");
}

// The appenders add to what is there and leave it alone (they write in place after one resize).
TEST(Describe, AppendHexKeepsThePrefix) {
  std::string s = "rx ";
  append_hex(s, test::bytes("53 0b 01 01 64 60 00 09 00 00 00 53 45"));
  EXPECT_EQ(s, "rx 53 0B 01 01 64 60 00 09 00 00 00 53 45");
  append_hex(s, std::span<const std::uint8_t>{});
  EXPECT_EQ(s, "rx 53 0B 01 01 64 60 00 09 00 00 00 53 45");
  s = "0x";
  append_hex(s, 0x0427u, 4);
  EXPECT_EQ(s, "0x0427");
  append_hex(s, 0xDEADBEEFu, 8);
  EXPECT_EQ(s, "0x0427DEADBEEF");
  append_hex(s, 0xFu, 0);
  EXPECT_EQ(s, "0x0427DEADBEEF");
  // every byte value round-trips
  std::vector<std::uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  const std::string text = hex(all);
  ASSERT_EQ(text.size(), 3 * 256 - 1);
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(std::stoi(text.substr(static_cast<std::size_t>(3 * i), 2), nullptr, 16), i);
  }
}

}  // namespace
}  // namespace mcemu::faulhaber
