// The virtual bus: SLCAN sessions and the real CANopen node on the MC349 dictionary. The §3.8
// examples that involve the node (rows 10–15, 33) end to end, byte for byte, minus TCP.
#include "device/canopen_bus.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <random>

#include "drive/model/model_preset.hpp"
#include "drive/od/model_tables.hpp"
#include "protocols/canopen/crc16.hpp"
#include "protocols/slcan/codec.hpp"

namespace mcemu::device {
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

// Bad input never breaks anything (README ground rule): 20 000 seeded random lines — SDO requests
// with random bytes (any command, index, sub, data), NMT and other frames, malformed Lawicel
// commands and binary noise — with time advancing in between. Every line gets an answer (CR, BEL,
// z/Z or a reply), and afterwards the node still serves SDO on whatever node-id the random writes
// left it with.
TEST(CanopenBus, RandomLinesNeverBreakTheSessionOrTheNode) {
  Rig r;
  auto s = r.bus.make_session();
  std::mt19937 rng(20261123);
  const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  static constexpr char k_hex[] = "0123456789ABCDEF";
  const auto hex = [&](int digits) {
    std::string h;
    for (int i = 0; i < digits; ++i) h.push_back(k_hex[pick(16)]);
    return h;
  };
  static constexpr std::array<std::uint8_t, 14> k_cs = {0x40, 0x2F, 0x2B, 0x23, 0x22, 0x21, 0x60,
                                                        0x70, 0x00, 0x10, 0xA4, 0xC6, 0xA1, 0x80};
  std::vector<std::pair<std::uint16_t, std::uint8_t>> entries;
  r.od.for_each([&](const od::EntryInfo& e, const od::Value&) { entries.emplace_back(e.index, e.sub); });
  int sdo_answers = 0;
  int sdo_aborts = 0;
  for (int i = 0; i < 20000; ++i) {
    std::string line;
    switch (pick(10)) {
      case 0:
      case 1:
      case 2:
      case 3: {  // an SDO request with a plausible command byte and random rest
        char cs[3];
        std::snprintf(cs, sizeof cs, "%02X", k_cs[static_cast<std::size_t>(pick(k_cs.size()))]);
        if (pick(2) == 0) {  // an entry that exists
          const auto& [index, sub] = entries[static_cast<std::size_t>(pick(static_cast<int>(entries.size())))];
          char addr[8];
          std::snprintf(addr, sizeof addr, "%02X%02X%02X", index & 0xFF, index >> 8, sub);
          line = std::string("t6328") + cs + addr + hex(8);
        } else {
          line = std::string("t6328") + cs + hex(14);
        }
        break;
      }
      case 4: line = "t632" + std::to_string(pick(9)) + hex(2 * pick(9)); break;  // any DLC
      case 5: line = "t000" + std::to_string(pick(3)) + hex(4); break;            // NMT, odd DLCs
      case 6: line = "t" + hex(3) + "8" + hex(16); break;                         // any identifier
      case 7: line = std::string(1, "tTrRZOCLSsVvNFXxMmWw"[pick(20)]) + hex(pick(12)); break;
      case 8:
        for (int k = 1 + pick(20); k > 0; --k) line.push_back(static_cast<char>(rng() & 0xFF));
        std::replace(line.begin(), line.end(), '\r', 'x');
        std::replace(line.begin(), line.end(), '\n', 'x');
        break;
      default: line = "O"; break;  // reopen if a random C closed the channel
    }
    s->receive(line + "\r");
    const std::string out = s->take_output();
    EXPECT_FALSE(out.empty()) << "line " << i << " unanswered: " << line;
    sdo_answers += out.find("t5B28") != std::string::npos ? 1 : 0;
    sdo_aborts += out.find("t5B2880") != std::string::npos ? 1 : 0;
    if (pick(4) == 0) r.bus.step();
    ASSERT_FALSE(s->finished()) << line;
  }
  EXPECT_GT(sdo_answers, 2000) << "the random lines reached the SDO server";
  EXPECT_GT(sdo_aborts, 500);
  EXPECT_LT(sdo_aborts, sdo_answers) << "and some of them were accepted";
  // the node is alive: abort whatever transfer is open, start it, and read 1000h
  const auto id = static_cast<unsigned>(r.bus.node().node_id());
  char buf[64];
  s->receive("C\rZ0\rO\r");  // a random Z1 may have switched timestamps on
  std::snprintf(buf, sizeof buf, "t%03X88000000000000000\rt000201%02X\r", 0x600 + id, id);
  s->receive(buf);
  (void)s->take_output();
  std::snprintf(buf, sizeof buf, "t%03X84000100000000000\r", 0x600 + id);
  s->receive(buf);
  std::snprintf(buf, sizeof buf, "t%03X84300100092010200\r", 0x580 + id);
  const std::string answer = s->take_output();
  EXPECT_NE(answer.find(buf), std::string::npos) << "node-id " << id << ": " << answer;
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

// Fault injection at the bus (slcan-canopen.md §11.3): a dropped node frame reaches no session; a
// held-back one comes out at its wall time, and later frames never overtake it; rawTx reaches every
// session; bel is asked per line.
struct FaultRig : Rig {
  std::chrono::milliseconds wall{1000};
  std::vector<std::chrono::milliseconds> scheduled;
  std::vector<std::string> traced;
  std::vector<device::Verdict> verdicts;  // the next frames' verdicts, then "send"
  int bel = 0;
  FaultRig() {
    CanopenBus::Faults f;
    f.node_frame = [this](const can::Frame&) {
      if (verdicts.empty()) return device::Verdict{};
      auto v = verdicts.front();
      verdicts.erase(verdicts.begin());
      return v;
    };
    f.bel = [this] {
      if (bel == 0) return false;
      --bel;
      return true;
    };
    f.wall_now = [this] { return wall; };
    f.schedule = [this](std::chrono::milliseconds due) { scheduled.push_back(due); };
    f.trace = [this](const std::string& t) { traced.push_back(t); };
    bus.set_faults(std::move(f));
  }
  static device::Verdict drop() {
    device::Verdict v;
    v.action = device::Verdict::Action::drop;
    v.fault_id = "f1";
    v.kind = device::TransportKind::slcan_drop_tx;
    return v;
  }
  static device::Verdict delay(std::chrono::milliseconds ms) {
    device::Verdict v;
    v.action = device::Verdict::Action::delay;
    v.delay = ms;
    v.fault_id = "f2";
    v.kind = device::TransportKind::slcan_delay_tx;
    return v;
  }
};

TEST(CanopenBusFaults, DroppedFrameReachesNoSession) {
  FaultRig r;
  auto a = r.bus.make_session();
  auto b = r.bus.make_session();
  r.verdicts = {FaultRig::drop()};
  a->receive("t63284041600000000000\r");
  EXPECT_EQ(a->take_output(), "z\r");
  EXPECT_EQ(b->take_output(), "");
  ASSERT_EQ(r.traced.size(), 1u);
  EXPECT_EQ(r.traced[0], "frame t5B284B41600040000000 not sent (fault f1 slcan.dropTx)");
  a->receive("t63284041600000000000\r");
  EXPECT_EQ(a->take_output(), "z\rt5B284B41600040000000\r") << "the next frame is sent";
}

TEST(CanopenBusFaults, HeldBackFramesKeepTheirOrder) {
  FaultRig r;
  auto a = r.bus.make_session();
  r.verdicts = {FaultRig::delay(200ms)};
  a->receive("t63284041600000000000\r");  // response held back 200 ms
  a->receive("t6328407a600000000000\r");  // not delayed itself, but queued behind
  EXPECT_EQ(a->take_output(), "z\rz\r");
  ASSERT_EQ(r.scheduled.size(), 1u);
  EXPECT_EQ(r.scheduled[0], 1200ms);
  r.wall = 1199ms;  // a timer that fired early
  r.bus.release_delayed();
  EXPECT_EQ(a->take_output(), "");
  ASSERT_EQ(r.scheduled.size(), 2u) << "asks again";
  EXPECT_EQ(r.scheduled[1], 1200ms);
  r.wall = 1200ms;
  r.bus.release_delayed();
  EXPECT_EQ(a->take_output(), "t5B284B41600040000000\rt5B28437A600000000000\r");
  EXPECT_FALSE(r.bus.next_release());
  EXPECT_EQ(r.scheduled.size(), 2u) << "nothing left to wait for";
}

TEST(CanopenBusFaults, RawTextAndBel) {
  FaultRig r;
  auto a = r.bus.make_session();
  auto b = r.bus.make_session();
  b->receive("C\r");  // closed: rawTx still reaches it
  EXPECT_EQ(b->take_output(), "\r");
  r.bus.send_raw("t7321\r");
  EXPECT_EQ(a->take_output(), "t7321\r");
  EXPECT_EQ(b->take_output(), "t7321\r");
  r.bel = 1;
  a->receive("V\rV\r");
  EXPECT_EQ(a->take_output(), "\aV1010\r");
}

// The lint's view of the bus: every client frame before the node, every node frame (whatever the
// transport faults do to it), every NMT state change with its direction.
TEST(CanopenBus, ObserverSeesFramesAndNmtChanges) {
  model::ModelPreset preset = *model::find_preset("MC349");
  od::ObjectDictionary od{preset};
  CanopenBus bus{od, {}, {}};
  std::vector<std::string> seen;
  CanopenBus::Observer o;
  o.client_frame = [&](const can::Frame& f) { seen.push_back("client " + std::to_string(f.id)); };
  o.node_frame = [&](const can::Frame& f) { seen.push_back("node " + std::to_string(f.id)); };
  o.nmt = [&](canopen::NmtState from, canopen::NmtState to) {
    seen.push_back("nmt " + std::to_string(static_cast<int>(from)) + ">" + std::to_string(static_cast<int>(to)));
  };
  bus.set_observer(std::move(o));
  CanopenBus::Faults drop;
  drop.node_frame = [](const can::Frame&) {
    Verdict v;
    v.action = Verdict::Action::drop;
    return v;
  };
  bus.set_faults(drop);
  bus.power_on();
  bus.step(10ms);  // boot-up: INITIALISING → PRE-OPERATIONAL
  auto s = bus.make_session();
  s->receive("t00020232\r");              // NMT stop node 50
  s->receive("t63284041600000000000\r");  // an SDO request: a STOPPED node does not answer
  s->receive("t00020132\r");              // NMT start
  s->receive("t63284041600000000000\r");  // answered (and dropped by the fault: still seen)
  const std::vector<std::string> want = {"nmt 0>127", "node 1842", "client 0", "nmt 127>4",   "client 1586", "client 0",
                                         "nmt 4>5",   "node 434",  "node 690", "client 1586", "node 1458"};
  EXPECT_EQ(seen, want);
}

}  // namespace
}  // namespace mcemu::device
