// The virtual bus: SLCAN sessions and the real CANopen node on the MC349 dictionary. The §3.8
// examples that involve the node (rows 10–15, 33) end to end, byte for byte, minus TCP.
#include "server/canopen_bus.hpp"

#include <gtest/gtest.h>

#include "drive/model/model_preset.hpp"

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

}  // namespace
}  // namespace mcemu::server
