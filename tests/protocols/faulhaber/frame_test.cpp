// Frame codec of faulhaber.md §3/§5: every example row decodes and encodes back byte for byte in
// both directions; the builders make the drive's rows exactly; decode() rejects what the receiver
// rejects.
#include "protocols/faulhaber/frame.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <map>

#include "tests/protocols/faulhaber/spec_frames.hpp"
#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

using test::bytes;

TEST(Frame, EverySpecRowDecodesAndEncodesBack) {
  for (const auto& row : test::k_spec_frames) {
    const auto wire = bytes(row.hex);
    const auto d = decode(wire);
    ASSERT_EQ(d.error, DecodeError::none) << row.name;
    EXPECT_EQ(d.frame.node, 1) << row.name;
    EXPECT_EQ(d.frame.data.size() + 4, wire[1]) << row.name;
    EXPECT_EQ(encode(d.frame), wire) << row.name;
    std::string out = "x";
    append_encoded(out, d.frame.view());
    std::string want = "x";
    want.append(test::chars(wire));
    EXPECT_EQ(out, want) << row.name;
  }
}

// Each drive → host row of §5 made by its builder.
TEST(Frame, BuildersMakeTheDriveRows) {
  const std::uint8_t v0040[] = {0x40, 0x00};
  const std::uint8_t v0427[] = {0x27, 0x04};
  const std::uint8_t minus1[] = {0xFF, 0xFF, 0xFF, 0xFF};
  const std::uint8_t nine[] = {0x09, 0, 0, 0};
  const std::uint8_t v0440[] = {0x40, 0x04};
  const std::map<std::string, Frame> built = {
      {"6041h = 0x0040", sdo_read_response(1, 0x6041, 0, v0040)},
      {"6041h = 0x0427", sdo_read_response(1, 0x6041, 0, v0427)},
      {"write response 6040h.00", sdo_write_response(1, 0x6040, 0)},
      {"write response 6060h.00", sdo_write_response(1, 0x6060, 0)},
      {"3005h.09 = -1", sdo_read_response(1, 0x3005, 9, minus1)},
      {"error 1234h.00 0x06020000", sdo_error_response(1, 0x1234, 0, 0x06020000)},
      {"error 6041h.00 0x06010002", sdo_error_response(1, 0x6041, 0, 0x06010002)},
      {"statusword 0x0040", statusword_notification(1, 0x0040)},
      {"statusword 0x0021", statusword_notification(1, 0x0021)},
      {"statusword 0x0027", statusword_notification(1, 0x0027)},
      {"statusword 0x0427", statusword_notification(1, 0x0427)},
      {"EMCY 3210h", emcy_notification(1, 0x3210, 0x05, 0x0004)},
      {"EMCY error reset", emcy_notification(1, 0, 0, 0)},
      {"boot MC 5005", boot_message(1, "MC 5005")},
      {"boot MCS 3242 BX4 ET", boot_message(1, "MCS 3242 BX4 ET")},
      {"controlword response OK", controlword_response(1, 0)},
      {"write response 2400h.04", sdo_write_response(1, 0x2400, 4)},
      {"EMCY 8611h", emcy_notification(1, 0x8611, 0x21, 0x0002)},
      {"answer to abort 1234h.00", abort_acknowledge(1, 0x1234, 0)},
      {"6064h = 9 (CRC 0x53)", sdo_read_response(1, 0x6064, 0, nine)},
      {"6041h = 0x0440", sdo_read_response(1, 0x6041, 0, v0440)},
      {"RS232 write response", sdo_write_response(1, 0x6040, 0)},
  };
  std::size_t drive_rows = 0;
  for (const auto& row : test::k_spec_frames) {
    if (row.to_drive) continue;
    ++drive_rows;
    const auto it = built.find(row.name);
    ASSERT_NE(it, built.end()) << "no builder case for " << row.name;
    EXPECT_EQ(encode(it->second), bytes(row.hex)) << row.name;
  }
  EXPECT_EQ(drive_rows, built.size());
}

TEST(Frame, ErrorResponseIsElevenLong) {
  const auto f = encode(sdo_error_response(7, 0xABCD, 0x12, 0x05040001));
  EXPECT_EQ(f[1], k_error_frame_length);
  EXPECT_EQ(f.size(), k_error_frame_length + 2);
  EXPECT_EQ(f[2], 7);
  EXPECT_EQ(f[3], command::sdo_error);
  EXPECT_EQ(std::vector<std::uint8_t>(f.begin() + 4, f.begin() + 11),
            (std::vector<std::uint8_t>{0xCD, 0xAB, 0x12, 0x01, 0x00, 0x04, 0x05}));
}

TEST(Frame, BootMessageIsCutAt58Bytes) {
  const std::string name(70, 'N');
  EXPECT_EQ(boot_message(1, name).data.size(), k_max_value);
  EXPECT_EQ(boot_message(1, "").data.size(), 0u);
  EXPECT_EQ(encode(boot_message(1, ""))[1], 4);
}

TEST(Frame, LongestFrame) {
  Frame f{1, 0x42, std::vector<std::uint8_t>(k_max_data, 0xAA)};
  const auto wire = encode(f);
  EXPECT_EQ(wire.size(), k_max_frame);
  EXPECT_EQ(wire[1], 255);
  EXPECT_EQ(decode(wire).frame, f);
  f.data.push_back(0);
  EXPECT_THROW(encode(f), std::length_error);
  std::string out;
  EXPECT_THROW(append_encoded(out, f.view()), std::length_error);
}

TEST(Frame, DecodeRejects) {
  struct Case {
    const char* name;
    std::string_view hex;
    DecodeError error;
  };
  const Case cases[] = {
      {"too short", "53 04 01 00 50", DecodeError::too_short},
      {"no SOF", "54 07 01 01 41 60 00 73 45", DecodeError::no_sof},
      {"L < 4", "53 03 01 00 50 45", DecodeError::bad_length},
      {"L too long for the bytes", "53 08 01 01 41 60 00 73 45", DecodeError::bad_length},
      {"L too short for the bytes", "53 06 01 01 41 60 00 73 45", DecodeError::bad_length},
      {"no EOF", "53 07 01 01 41 60 00 73 46", DecodeError::bad_eof},
      {"bad CRC", "53 07 01 01 41 60 00 74 45", DecodeError::bad_crc},
  };
  for (const auto& c : cases) EXPECT_EQ(decode(bytes(c.hex)).error, c.error) << c.name;
  EXPECT_EQ(decode(bytes("53 07 01 01 41 60 00 74 45"), false).error, DecodeError::none);
}

TEST(Frame, LittleEndianHelpers) {
  const std::uint8_t d[] = {0x01, 0x02, 0x03, 0x04, 0x05};
  EXPECT_EQ(le16(d, 0), 0x0201);
  EXPECT_EQ(le16(d, 3), 0x0504);
  EXPECT_EQ(le32(d, 1), 0x05040302u);
}

}  // namespace
}  // namespace mcemu::faulhaber
