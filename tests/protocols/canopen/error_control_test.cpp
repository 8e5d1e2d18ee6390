// Heartbeat producer and node/life guarding (slcan-canopen.md §5; conformance HB-01 … HB-06,
// GRD-01 … GRD-06, HBG-01 … HBG-07) in simulated time.
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

std::vector<Millis> heartbeat_times(const Harness& h) {
  std::vector<Millis> t;
  for (const auto& [at, line] : h.log) {
    if (line.rfind("t7321", 0) == 0 && line != "t732100\r") t.push_back(at);  // not the boot-up
  }
  return t;
}

TEST(Heartbeat, OffByDefault) {  // HB-01, HBG-07
  Harness h;
  h.boot();
  EXPECT_EQ(h.wait(10s), "");
  EXPECT_EQ(h.tick(100), "");
}

TEST(Heartbeat, ExactCadenceFromTheWrite) {  // HB-02, §5.1 example
  Harness h;
  h.boot();
  h.wait(37ms);
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("t63282B171000E8030000"), "t5B286017100000000000\r");
  h.run_until(t0 + 10s);
  const auto t = heartbeat_times(h);
  ASSERT_EQ(t.size(), 10u);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_EQ(t[k], t0 + Millis(1000 * (k + 1)));
  // with the server's 1 ms loop the cadence is the same
  Harness s;
  s.boot();
  s.send("t63282B171000E8030000");
  const Millis s0 = s.now;
  std::string out = s.tick(2999);
  EXPECT_EQ(out, "t73217F\rt73217F\r");
  EXPECT_EQ(heartbeat_times(s), (std::vector<Millis>{s0 + 1000ms, s0 + 2000ms}));
  EXPECT_EQ(s.tick(1), "t73217F\r");
}

TEST(Heartbeat, StateByteFollowsNmt) {  // HB-03, HB-04, HBG-04
  Harness h;
  h.boot();
  h.send("t63282B17100064000000");  // 100 ms
  EXPECT_EQ(h.wait(100ms), "t73217F\r");
  h.send("t00020132");
  h.send("t63282B17100064000000");  // restart the period at this write
  EXPECT_EQ(h.wait(100ms), "t732105\r");
  h.send("t00020232");
  EXPECT_EQ(h.wait(100ms), "t732104\r");
  EXPECT_EQ(h.wait(100ms), "t732104\r");
}

TEST(Heartbeat, PeriodChangeTakesEffectAtTheWrite) {  // HB-06
  Harness h;
  h.boot();
  h.send("t63282B171000E8030000");  // 1000
  h.wait(1500ms);
  const Millis t = h.now;
  h.send("t63282B171000C8000000");  // 200
  EXPECT_EQ(h.number(0x1017, 0), 200);
  EXPECT_EQ(h.run_until(t + 199ms), "");
  EXPECT_EQ(h.run_until(t + 200ms), "t73217F\r");
  h.send("t63282B17100000000000");  // 0 stops it
  EXPECT_EQ(h.wait(5s), "");
}

TEST(Heartbeat, SameValueWrittenRestartsThePeriod) {
  Harness h;
  h.boot();
  h.send("t63282B171000E8030000");
  h.wait(600ms);
  const Millis t = h.now;
  h.send("t63282B171000E8030000");
  EXPECT_EQ(h.run_until(t + 999ms), "");
  EXPECT_EQ(h.run_until(t + 1000ms), "t73217F\r");
}

TEST(Heartbeat, BulkLoadedPeriodIsPickedUp) {  // 1011h restore path: no write hook runs
  Harness h;
  h.boot();
  std::vector<od::StoredValue> v{{0x1017, 0, od::Value{std::int64_t{250}}}};
  h.od->load_values(v);
  h.node->reload();
  const Millis t = h.now;
  EXPECT_EQ(h.run_until(t + 250ms), "t73217F\r");
}

TEST(Guarding, ToggleAlternatesPerReply) {  // GRD-01, §3.8 row 14
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("r7321"), "t73217F\r");
  EXPECT_EQ(h.send("r7321"), "t7321FF\r");
  EXPECT_EQ(h.send("r7320"), "t73217F\r");  // any DLC
  EXPECT_EQ(h.send("r7328"), "t7321FF\r");
  EXPECT_EQ(h.send("t7321FF"), "");  // a data frame on 0x732 is not a guarding request
  EXPECT_EQ(h.send("r7331"), "");    // another node
}

TEST(Guarding, ResetCommunicationResetsTheToggle) {  // GRD-02
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("r7321"), "t73217F\r");
  h.send("t00028232");
  EXPECT_EQ(h.send("r7321"), "");  // no reply while initialising
  h.wait(10ms);
  EXPECT_EQ(h.send("r7321"), "t73217F\r");
}

TEST(Guarding, StateBytes) {  // GRD-03
  Harness h;
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("r7321"), "t732105\r");
  EXPECT_EQ(h.send("r7321"), "t732185\r");
  h.send("t00020232");
  EXPECT_EQ(h.send("r7321"), "t732104\r");
  EXPECT_EQ(h.send("r7321"), "t732184\r");
}

struct LifeGuarding {
  int lost = 0;
  Harness* h = nullptr;
  Node::Hooks hooks() {
    Node::Hooks k;
    k.connection_lost = [this] {
      ++lost;
      h->node->emit_emcy(0x8130, 0x10);  // what the core does with 6007h = 1 (drive-core.md §11.6)
    };
    return k;
  }
};

TEST(Guarding, LifeTimeExpiry) {  // GRD-04
  LifeGuarding lg;
  Harness h("MC349", {}, false, lg.hooks());
  lg.h = &h;
  h.boot();
  h.send("t63282B0C100064000000");  // 100Ch = 100
  h.send("t63282F0D100003000000");  // 100Dh = 3
  h.send("t00020132");
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("r7321"), "t732105\r");
  EXPECT_EQ(h.run_until(t0 + 299ms), "");
  EXPECT_EQ(lg.lost, 0);
  EXPECT_EQ(h.run_until(t0 + 300ms), "t0B283081100000000000\r");
  EXPECT_EQ(lg.lost, 1);
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);  // 1029h.01 = 0
  EXPECT_EQ(h.wait(5s), "");                              // once per arming
  EXPECT_EQ(lg.lost, 1);
  // an RTR re-arms it; RTRs inside the life time keep it alive
  EXPECT_EQ(h.send("r7321"), "t7321FF\r");
  h.wait(200ms);
  h.send("r7321");
  h.wait(200ms);
  EXPECT_EQ(lg.lost, 1);
  h.wait(100ms);
  EXPECT_EQ(lg.lost, 2);
}

TEST(Guarding, NmtReactionOf1029) {  // GRD-05
  for (int reaction : {1, 2}) {
    LifeGuarding lg;
    Harness h("MC349", {}, false, lg.hooks());
    lg.h = &h;
    h.boot();
    h.set(0x100C, 0, 100);
    h.set(0x100D, 0, 3);
    h.set(0x1029, 1, reaction);
    h.send("t00020132");
    h.send("r7321");
    h.wait(300ms);
    EXPECT_EQ(lg.lost, 1);
    EXPECT_EQ(h.node->state(), reaction == 1 ? NmtState::operational : NmtState::stopped);
  }
}

TEST(Guarding, NoLifeGuardingWithZeroTimes) {  // GRD-06
  for (auto [gt, lf] : {std::pair{0, 3}, std::pair{100, 0}}) {
    LifeGuarding lg;
    Harness h("MC349", {}, false, lg.hooks());
    lg.h = &h;
    h.boot();
    h.set(0x100C, 0, gt);
    h.set(0x100D, 0, lf);
    EXPECT_EQ(h.send("r7321"), "t73217F\r");
    h.wait(60s);
    EXPECT_EQ(lg.lost, 0);
  }
}

TEST(HeartbeatVersusGuarding, RtrIgnoredWhileHeartbeatRuns) {  // HBG-01, HBG-02
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("r7321"), "t73217F\r");
  h.send("t63282B171000E8030000");
  EXPECT_EQ(h.send("r7321"), "");
  h.send("t63282B17100000000000");
  EXPECT_EQ(h.send("r7321"), "t7321FF\r");  // the toggle continues where it stopped
}

TEST(HeartbeatVersusGuarding, NoLifeGuardingWhileHeartbeat) {  // HBG-03, HBG-05
  LifeGuarding lg;
  Harness h("MC349", {}, false, lg.hooks());
  lg.h = &h;
  h.boot();
  h.set(0x100C, 0, 100);
  h.set(0x100D, 0, 3);
  h.send("r7321");  // armed
  h.wait(100ms);
  h.send("t63282B171000E8030000");  // heartbeat on: the pending timeout is cancelled
  h.wait(10s);
  EXPECT_EQ(lg.lost, 0);
  h.send("t63282B17100000000000");  // back to 0: inactive until the next RTR
  h.wait(10s);
  EXPECT_EQ(lg.lost, 0);
  h.send("r7321");
  h.wait(300ms);
  EXPECT_EQ(lg.lost, 1);
}

}  // namespace
}  // namespace mcemu::canopen::test
