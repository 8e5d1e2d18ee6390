// The command table of faulhaber.md §5 on a small dictionary: every host → drive row of the §5
// example table answered byte for byte; layout errors; unsupported codes; the byte rules of an SDO
// download (0x06070012/13); the 0x2400.05 range; controlword errors through a refusing write hook;
// the node-id a response carries; a write the dictionary completes later (Store).
#include "protocols/faulhaber/commands.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <optional>

#include "protocols/faulhaber/describe.hpp"
#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

using test::bytes;
using test::request;

struct Fixture {
  std::unique_ptr<od::ObjectDictionary> od = test::make_dictionary();
  Commands commands{*od};
  std::optional<Frame> later_frame;
  od::AbortCode later_code = od::AbortCode::none;

  Outcome run(std::string_view request_hex, std::uint8_t node = 1) {
    const auto d = decode(bytes(request_hex), false);
    EXPECT_EQ(d.error, DecodeError::none) << request_hex;
    return commands.handle(d.frame.view(), node, [this](Frame f, od::AbortCode code) {
      later_frame = std::move(f);
      later_code = code;
    });
  }
  // The response's wire bytes as hex; "none" for no response, "pending" for a pending write.
  std::string answer(std::string_view request_hex, std::uint8_t node = 1) {
    const Outcome o = run(request_hex, node);
    if (o.kind == Outcome::Kind::none) return "none";
    if (o.kind == Outcome::Kind::pending) return "pending";
    return hex(encode(o.response));
  }
  std::int64_t value(std::uint16_t index, std::uint8_t sub) const { return *od->read_number(index, sub); }
};

std::string error(std::uint16_t index, std::uint8_t sub, std::uint32_t code, std::uint8_t node = 1) {
  return hex(encode(sdo_error_response(node, index, sub, code)));
}

struct Row {
  const char* name;
  std::function<void(od::ObjectDictionary&)> setup;
  std::string request;
  std::string response;
};

std::vector<Row> spec_rows() {
  return {
      {"read 6041h = 0x0040", {}, "53 07 01 01 41 60 00 73 45", "53 09 01 01 41 60 00 40 00 C2 45"},
      {"read 6041h = 0x0427", [](auto& od) { test::set(od, 0x6041, 0, 0x0427); }, "53 07 01 01 41 60 00 73 45",
       "53 09 01 01 41 60 00 27 04 F4 45"},
      {"write 6040h.00 = 0x0006", {}, "53 09 01 02 40 60 00 06 00 2C 45", "53 07 01 02 40 60 00 DB 45"},
      {"write 6040h.00 = 0x000F", {}, "53 09 01 02 40 60 00 0F 00 25 45", "53 07 01 02 40 60 00 DB 45"},
      {"write 6060h.00 = 3", {}, "53 08 01 02 60 60 00 03 A2 45", "53 07 01 02 60 60 00 FB 45"},
      {"write 60FFh.00 = 100",
       {},
       "53 0B 01 02 FF 60 00 64 00 00 00 59 45",
       hex(encode(sdo_write_response(1, 0x60FF, 0)))},
      {"read 3005h.09 = -1", [](auto& od) { test::set(od, 0x3005, 9, -1); }, "53 07 01 01 05 30 09 3B 45",
       "53 0B 01 01 05 30 09 FF FF FF FF 9D 45"},
      {"read 1234h.00 (missing)", {}, "53 07 01 01 34 12 00 8B 45", "53 0B 01 03 34 12 00 00 00 02 06 2B 45"},
      {"write 6041h.00 (read-only)", {}, "53 09 01 02 41 60 00 00 00 2B 45", "53 0B 01 03 41 60 00 02 00 01 06 78 45"},
      {"reset node", {}, "53 04 01 00 50 45", "none"},
      {"controlword 0x0006", {}, "53 06 01 04 06 00 50 45", "53 05 01 04 00 55 45"},
      {"controlword 0x000F", {}, "53 06 01 04 0F 00 59 45", "53 05 01 04 00 55 45"},
      {"write 2400h.04 = 0x00010000", {}, "53 0B 01 02 00 24 04 00 00 01 00 29 45", "53 07 01 02 00 24 04 8E 45"},
      {"abort request 1234h.00", {}, request(0x03, "34 12 00 00 00 00 08"), "53 07 01 03 34 12 00 DC 45"},
      {"read 6064h = 9 (third-party reference)", [](auto& od) { test::set(od, 0x6064, 0, 9); },
       "53 07 01 01 64 60 00 56 45", "53 0B 01 01 64 60 00 09 00 00 00 53 45"},
      {"read 6041h = 0x0440 (third-party reference)", [](auto& od) { test::set(od, 0x6041, 0, 0x0440); },
       "53 07 01 01 41 60 00 73 45", "53 09 01 01 41 60 00 40 04 6C 45"},
  };
}

TEST(Commands, SpecRowsByteForByte) {
  for (const auto& row : spec_rows()) {
    Fixture f;
    if (row.setup) row.setup(*f.od);
    EXPECT_EQ(f.answer(row.request), row.response) << row.name;
  }
}

TEST(Commands, WritesReachTheDictionary) {
  Fixture f;
  f.answer("53 09 01 02 40 60 00 0F 00 25 45");
  EXPECT_EQ(f.value(0x6040, 0), 0x000F);
  f.answer("53 08 01 02 60 60 00 03 A2 45");
  EXPECT_EQ(f.value(0x6060, 0), 3);
  f.answer("53 0B 01 02 FF 60 00 64 00 00 00 59 45");
  EXPECT_EQ(f.value(0x60FF, 0), 100);
  f.answer(request(0x02, "FF 60 00 9C FF FF FF"));  // I32 -100
  EXPECT_EQ(f.value(0x60FF, 0), -100);
  f.answer(request(0x02, "60 60 00 FF"));  // I8 -1
  EXPECT_EQ(f.value(0x6060, 0), -1);
  f.answer("53 06 01 04 06 00 50 45");
  EXPECT_EQ(f.value(0x6040, 0), 6);
  f.answer("53 0B 01 02 00 24 04 00 00 01 00 29 45");
  EXPECT_EQ(f.value(0x2400, 4), 0x00010000);
}

TEST(Commands, ErrorsAndLayouts) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      // unsupported codes: index/sub-index from the data when present
      {request(0x06, "41 60 00"), error(0x6041, 0, 0x05040001)},
      {request(0x06, ""), error(0, 0, 0x05040001)},
      {request(0x08, "08 10 00"), error(0x1008, 0, 0x05040001)},
      {request(0x09, "08 10 00 00"), error(0x1008, 0, 0x05040001)},
      {request(0x0A, ""), error(0, 0, 0x05040001)},
      {request(0x0B, "08 10 00 07 00 00 00"), error(0x1008, 0, 0x05040001)},
      {request(0x0C, "01 02"), error(0, 0, 0x05040001)},
      {request(0x0D, "34 12 05"), error(0x1234, 5, 0x05040001)},
      {request(0x05, "40 00"), error(0, 0, 0x05040001)},
      {request(0x07, "10 32 05 04 00 00 00 00"), error(0x3210, 5, 0x05040001)},
      {request(0xFF, "41 60 00"), error(0x6041, 0, 0x05040001)},
      // layouts
      {request(0x01, "41 60"), error(0, 0, 0x05040001)},
      {request(0x01, ""), error(0, 0, 0x05040001)},
      {request(0x01, "41 60 00 00"), error(0x6041, 0, 0x05040001)},
      {request(0x02, "40 60"), error(0, 0, 0x05040001)},
      {request(0x03, "34 12 00 00"), error(0x1234, 0, 0x05040001)},
      {request(0x03, "34 12 00 00 00 00 08 00"), error(0x1234, 0, 0x05040001)},
      // the byte rules of an SDO download with the length indicated (object-dictionary.md §3.1)
      {request(0x02, "00 24 04 00"), error(0x2400, 4, 0x06070013)},
      {request(0x02, "00 24 04 00 00 01"), error(0x2400, 4, 0x06070013)},
      {request(0x02, "00 24 04 00 00 01 00 00"), error(0x2400, 4, 0x06070012)},
      {request(0x02, "40 60 00"), error(0x6040, 0, 0x06070013)},
      {request(0x02, "40 60 00 06 00 00 00"), error(0x6040, 0, 0x06070012)},
      {request(0x02, "60 60 00 01 00"), error(0x6060, 0, 0x06070012)},
      // dictionary rules
      {request(0x02, "00 24 05 02"), error(0x2400, 5, 0x06090030)},
      {request(0x02, "34 12 00 01"), error(0x1234, 0, 0x06020000)},
      {request(0x01, "00 24 09"), error(0x2400, 9, 0x06090011)},
      {request(0x02, "08 10 00 41"), error(0x1008, 0, 0x06010002)},
      // controlword of the wrong length: refused like that 6040h.00 write
      {request(0x04, "06"), hex(encode(controlword_response(1, 1)))},
      {request(0x04, "06 00 00"), hex(encode(controlword_response(1, 1)))},
      {request(0x04, ""), hex(encode(controlword_response(1, 1)))},
      // reset node ignores data bytes (AN191 sends L = 6)
      {request(0x00, "12 34"), "none"},
  };
  for (const auto& [req, want] : cases) {
    Fixture f;
    EXPECT_EQ(f.answer(req), want) << req;
  }
}

TEST(Commands, NetModeRange) {
  Fixture f;
  EXPECT_EQ(f.answer(request(0x02, "00 24 05 01")), hex(encode(sdo_write_response(1, 0x2400, 5))));
  EXPECT_EQ(f.value(0x2400, 5), 1);
  EXPECT_EQ(f.answer(request(0x02, "00 24 05 02")), error(0x2400, 5, 0x06090030));
  EXPECT_EQ(f.value(0x2400, 5), 1) << "a refused write changes nothing";
}

TEST(Commands, ResetNodeAsksTheOwner) {
  for (const char* req : {"53 04 01 00 50 45", "53 06 01 00 00 00 00 45"}) {
    Fixture f;
    const auto d = decode(bytes(req), false);
    const Outcome o = f.commands.handle(d.frame.view(), 1, {});
    EXPECT_EQ(o.kind, Outcome::Kind::none) << req;
    EXPECT_TRUE(o.reset_node) << req;
  }
}

TEST(Commands, ControlwordRefusedByAWriteHookAnswersErrorByte1) {
  Fixture f;
  f.od->on_write(0x6040, 0, [](od::WriteRequest& r) {
    return std::get<std::int64_t>(r.value) == 0x0080 ? od::AbortCode::device_state : od::AbortCode::none;
  });
  const Outcome refused = f.run(request(0x04, "80 00"));
  EXPECT_EQ(hex(encode(refused.response)), hex(encode(controlword_response(1, 1))));
  EXPECT_EQ(refused.code, od::AbortCode::device_state);
  EXPECT_EQ(f.value(0x6040, 0), 0);
  EXPECT_EQ(f.answer("53 06 01 04 0F 00 59 45"), "53 05 01 04 00 55 45");
  EXPECT_EQ(f.value(0x6040, 0), 0x0F);
  // the same refusal through an SDO write is an error response with the hook's code
  EXPECT_EQ(f.answer(request(0x02, "40 60 00 80 00")), error(0x6040, 0, 0x08000022));
}

TEST(Commands, ResponsesCarryTheNodeIdInUse) {
  Fixture f;
  EXPECT_EQ(f.run("53 07 01 01 41 60 00 73 45", 9).response.node, 9);
  // a write of 0x2400.03 is answered with the id the request was addressed to
  EXPECT_EQ(f.answer(request(0x02, "00 24 03 07")), hex(encode(sdo_write_response(1, 0x2400, 3))));
  EXPECT_EQ(f.value(0x2400, 3), 7);
}

TEST(Commands, ReadSizesAndStrings) {
  Fixture f;
  test::set(*f.od, 0x6060, 0, -3);
  EXPECT_EQ(f.answer(request(0x01, "60 60 00")), hex(encode(Frame{1, 0x01, bytes("60 60 00 FD")})));
  EXPECT_EQ(f.answer(request(0x01, "00 24 04")), hex(encode(Frame{1, 0x01, bytes("00 24 04 00 00 03 00")})));
  EXPECT_EQ(f.answer(request(0x01, "05 30 00")), hex(encode(Frame{1, 0x01, bytes("05 30 00 1A")})));
  EXPECT_EQ(f.answer(request(0x01, "08 10 00")), hex(encode(Frame{1, 0x01, bytes("08 10 00 4D 43 20 35 30 30 35")})));
  (void)f.od->write(0x1008, 0, od::Value{std::string(70, 'x')}, od::Origin::internal);
  const Outcome o = f.run(request(0x01, "08 10 00"));
  EXPECT_EQ(o.response.data.size(), 3 + k_max_value) << "a string is cut at 58 bytes";
}

TEST(Commands, PendingWriteAnswersLater) {
  Fixture f;
  od::Done held;
  f.od->on_write(0x1010, 1, [&held](od::WriteRequest& r) {
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  const std::string store = request(0x02, "10 10 01 73 61 76 65");  // "save"
  EXPECT_EQ(f.answer(store), "pending");
  EXPECT_FALSE(f.later_frame);
  ASSERT_TRUE(held);
  held(od::AbortCode::none);
  ASSERT_TRUE(f.later_frame);
  EXPECT_EQ(hex(encode(*f.later_frame)), hex(encode(sdo_write_response(1, 0x1010, 1))));
  EXPECT_EQ(f.answer(store), "pending");
  held(od::AbortCode::cannot_store);
  EXPECT_EQ(hex(encode(*f.later_frame)), error(0x1010, 1, 0x08000020));
  EXPECT_EQ(f.later_code, od::AbortCode::cannot_store);
}

TEST(Commands, Names) {
  EXPECT_STREQ(Commands::name(0x00), "reset node");
  EXPECT_STREQ(Commands::name(0x01), "SDO read");
  EXPECT_STREQ(Commands::name(0x02), "SDO write");
  EXPECT_STREQ(Commands::name(0x03), "abort request");
  EXPECT_STREQ(Commands::name(0x04), "controlword");
  for (unsigned c = 0x05; c < 0x100; ++c) EXPECT_STREQ(Commands::name(static_cast<std::uint8_t>(c)), "unsupported");
}

}  // namespace
}  // namespace mcemu::faulhaber
