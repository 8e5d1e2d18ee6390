// The virtual bus: SLCAN sessions and the real CANopen node on the MC349 dictionary. The §3.8
// examples that involve the node (rows 10–15, 33) end to end, byte for byte, minus TCP.
#include "server/canopen_bus.hpp"

#include <gtest/gtest.h>

#include "drive/model/model_preset.hpp"
#include "drive/od/model_tables.hpp"
#include "protocols/canopen/crc16.hpp"
#include "protocols/slcan/codec.hpp"

namespace mcemu::server {
namespace {

using namespace std::chrono_literals;

struct Rig {
  model::ModelPreset preset = *model::find_preset("MC349");
  od::ObjectDictionary od{preset};
  CanopenBus bus{od, {}, {}};
  Rig() {
    bus.power_on();
    bus.step(10ms);  // boot-up, seen by nobody
  }
};

TEST(CanopenBus, SpecExamplesWithTheRealNode) {
  Rig r;
  auto s = r.bus.make_session();
  EXPECT_EQ(s->take_output(), "");  // row 1: nothing on connect
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"t63284041600000000000\r", "z\rt5B284B41600040000000\r"},  // 10
      {"t6328407a600000000000\r", "z\rt5B28437A600000000000\r"},  // 11
      {"t00020132\r", "z\rt1B224000\rt2B23400000\r"},             // 12
      {"T12ABCDEF2AA55\r", "Z\r"},                                // 13
      {"r7321\r", "z\rt732105\r"},                                // 14 (OPERATIONAL after row 12)
  };
  for (const auto& [in, out] : rows) {
    s->receive(in);
    EXPECT_EQ(s->take_output(), out) << in;
  }
}

TEST(CanopenBus, GuardingReplyInPreOperational) {  // row 14 as written (PRE-OPERATIONAL)
  Rig r;
  auto s = r.bus.make_session();
  s->receive("r7321\r");
  EXPECT_EQ(s->take_output(), "z\rt73217F\r");
}

TEST(CanopenBus, TimestampedHeartbeat) {  // row 15: heartbeat at t = 6703 ms after Z1
  Rig r;
  auto s = r.bus.make_session();
  s->receive("Z1\r");
  EXPECT_EQ(s->take_output(), "\r");
  r.bus.step(6703ms - r.bus.now() - 1000ms);  // write 1017h = 1000 at 5703 ms
  s->receive("t63282B171000E8030000\r");
  EXPECT_EQ(s->take_output(), "z\rt5B2860171000000000001647\r");
  for (int i = 0; i < 1000; ++i) r.bus.step();
  EXPECT_EQ(r.bus.now(), 6703ms);
  EXPECT_EQ(s->take_output(), "t73217F1A2F\r");
}

TEST(CanopenBus, TwoClientsOneBus) {  // row 33, §3.7
  Rig r;
  auto a = r.bus.make_session();
  auto b = r.bus.make_session();
  a->receive("t63284041600000000000\r");
  EXPECT_EQ(a->take_output(), "z\rt5B284B41600040000000\r");
  EXPECT_EQ(b->take_output(), "t5B284B41600040000000\r");
  // NMT from B changes the node for everybody; A sees the TPDOs too
  b->receive("t00020132\r");
  EXPECT_EQ(b->take_output(), "z\rt1B224000\rt2B23400000\r");
  EXPECT_EQ(a->take_output(), "t1B224000\rt2B23400000\r");
  // a closed session gets nothing, a listening one everything
  a->receive("C\r");
  b->receive("L\r");
  (void)a->take_output();
  (void)b->take_output();
  r.od.write(0x6041, 0, od::Value{std::int64_t{0x21}}, od::Origin::internal);
  r.bus.step();
  EXPECT_EQ(a->take_output(), "");
  EXPECT_EQ(b->take_output(), "t1B222100\rt2B23210000\r");
}

TEST(CanopenBus, SessionsDetachWhenDestroyed) {
  Rig r;
  auto a = r.bus.make_session();
  {
    auto b = r.bus.make_session();
    EXPECT_EQ(r.bus.session_count(), 2u);
  }
  EXPECT_EQ(r.bus.session_count(), 1u);
  a->receive("t63282B17100064000000\r");  // heartbeat 100 ms
  (void)a->take_output();
  for (int i = 0; i < 100; ++i) r.bus.step();
  EXPECT_EQ(a->take_output(), "t73217F\r");
}

TEST(CanopenBus, SessionMayOutliveTheBus) {
  std::unique_ptr<line::StreamSession> s;
  {
    Rig r;
    s = r.bus.make_session();
  }
  s->receive("t63284041600000000000\rV\r");
  EXPECT_EQ(s->take_output(), "z\rV1010\r");
  s.reset();
}

TEST(CanopenBus, ResetCommunicationKeepsSessionsAndSendsBootUp) {  // §4.4: connections stay
  Rig r;
  auto a = r.bus.make_session();
  a->receive("t00028232\r");
  EXPECT_EQ(a->take_output(), "z\r");
  for (int i = 0; i < 10; ++i) r.bus.step();
  EXPECT_EQ(a->take_output(), "t732100\r");
  EXPECT_FALSE(a->finished());
}

TEST(CanopenBus, MalformedInputGetsBelAndTheSessionContinues) {
  Rig r;
  auto a = r.bus.make_session();
  a->receive("t63G0\rt6328404160\r\x01\rt63284041600000000000\r");
  EXPECT_EQ(a->take_output(), "\a\a\az\rt5B284B41600040000000\r");
}

// SDO-22 through the whole pure stack (SLCAN text → session → bus → node → OD and back): a 100 kB
// block download into a rw string entry of a test dictionary, then a block upload of it. No object
// of a shipped model can hold 100 kB (slcan-canopen.md §12 SDO-22 names a unit-test dictionary).
TEST(CanopenBus, HundredKilobytesByBlockTransferAsSlcanLines) {
  const auto preset = *model::find_preset("MC349");
  auto entries = od::build_entries(preset);
  od::EntryInfo domain;
  domain.index = 0x2F00;
  domain.type = od::DataType::visible_string;
  domain.access = od::Access::rw;
  domain.cls = od::EntryClass::param;
  domain.factory = od::Value{std::string{}};
  entries.push_back(domain);
  od::ObjectDictionary od(std::move(entries));
  CanopenBus bus(od, {}, {});
  bus.start();
  auto s = bus.make_session();
  const auto request = [&](std::array<std::uint8_t, 8> bytes) {
    s->receive(slcan::encode_frame(can::Frame{0x632, false, false, 8, bytes}));
    std::string out = s->take_output();
    EXPECT_EQ(out.substr(0, 2), "z\r");
    return out.substr(2);
  };
  const auto response = [](const std::string& line) {
    auto r = slcan::parse_line(std::string_view(line).substr(0, line.size() - 1));
    return std::get<slcan::Command>(r).frame;
  };
  std::vector<std::uint8_t> data(100 * 1024);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(0x20 + (i * 7919) % 95);
  const std::uint32_t size = static_cast<std::uint32_t>(data.size());
  auto init = response(request({0xC6, 0x00, 0x2F, 0x00, static_cast<std::uint8_t>(size),
                                static_cast<std::uint8_t>(size >> 8), static_cast<std::uint8_t>(size >> 16), 0}));
  ASSERT_EQ(init.data[0], 0xA4);
  int blksize = init.data[4];
  std::size_t pos = 0;
  int seq = 0;
  int sub_blocks = 0;
  while (pos < data.size()) {
    std::array<std::uint8_t, 8> seg{};
    ++seq;
    const std::size_t n = std::min<std::size_t>(7, data.size() - pos);
    const bool last = pos + n == data.size();
    seg[0] = static_cast<std::uint8_t>((last ? 0x80 : 0) | seq);
    std::copy_n(data.begin() + static_cast<std::ptrdiff_t>(pos), n, seg.begin() + 1);
    pos += n;
    const std::string out = request(seg);
    if (last || seq == blksize) {
      const auto ack = response(out);
      ASSERT_EQ(ack.data[0], 0xA2);
      ASSERT_EQ(ack.data[1], seq);
      blksize = ack.data[2];
      seq = 0;
      ++sub_blocks;
    } else {
      ASSERT_EQ(out, "");
    }
  }
  EXPECT_GT(sub_blocks, 100);
  const std::uint16_t crc = canopen::crc16_ccitt(data);
  const int unused = static_cast<int>((7 - data.size() % 7) % 7);
  EXPECT_EQ(request({static_cast<std::uint8_t>(0xC1 | (unused << 2)), static_cast<std::uint8_t>(crc & 0xFF),
                     static_cast<std::uint8_t>(crc >> 8)}),
            "t5B28A100000000000000\r");
  EXPECT_EQ(std::get<std::string>(*od.read(0x2F00, 0)), std::string(data.begin(), data.end()));
  // and back by block upload, blksize 127
  auto up = response(request({0xA4, 0x00, 0x2F, 0x00, 127}));
  ASSERT_EQ(up.data[0], 0xC6);
  std::vector<std::uint8_t> back;
  std::string out = request({0xA3});
  for (;;) {
    ASSERT_EQ(out.size() % 22, 0u);
    int segments = 0;
    bool last = false;
    for (std::size_t at = 0; at < out.size(); at += 22) {
      const auto seg = response(out.substr(at, 22));
      ASSERT_EQ(seg.data[0] & 0x7F, ++segments);
      back.insert(back.end(), seg.data.begin() + 1, seg.data.end());
      last = (seg.data[0] & 0x80) != 0;
    }
    out = request({0xA2, static_cast<std::uint8_t>(segments), 127});
    if (last) break;
  }
  const auto end = response(out);
  ASSERT_EQ(end.data[0] & 0xE3, 0xC1);
  back.resize(back.size() - ((end.data[0] >> 2) & 7));
  EXPECT_EQ(back, data);
  EXPECT_EQ(end.data[1] | (end.data[2] << 8), crc);
  EXPECT_EQ(request({0xA1}), "");
}

}  // namespace
}  // namespace mcemu::server
