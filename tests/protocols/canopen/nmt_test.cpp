// NMT, boot-up, resets and node-id (slcan-canopen.md §4; conformance NMT-01 … NMT-08, OTH-09,
// OTH-10, HBG-06, NMT-09) at unit level.
#include <gtest/gtest.h>

#include "protocols/canopen/comm_reload.hpp"
#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

TEST(Nmt, PowerOnBootsAfter10msIntoPreOperational) {  // NMT-01
  Harness h;
  h.node->power_on(0ms);
  EXPECT_EQ(h.node->state(), NmtState::initialising);
  EXPECT_EQ(h.send("t63284041600000000000"), "");  // ignored while initialising
  EXPECT_EQ(h.send("r7321"), "");
  EXPECT_EQ(h.run_until(9ms), "");
  EXPECT_EQ(h.run_until(10ms), "t732100\r");
  EXPECT_EQ(h.log.back().first, 10ms);
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  h.set(0x6041, 0, 0x21);
  EXPECT_EQ(h.tick(5), "");    // no PDO in PRE-OPERATIONAL
  EXPECT_EQ(h.wait(60s), "");  // never starts itself, no heartbeat by default
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
}

TEST(Nmt, StartSendsEventTpdosOnceAndAgainNothing) {  // NMT-02, §3.8 row 12
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t00020132"), "t1B224000\rt2B23400000\r");
  EXPECT_EQ(h.node->state(), NmtState::operational);
  EXPECT_EQ(h.send("t00020132"), "");
  EXPECT_EQ(h.send("t00020100"), "");  // all nodes
}

TEST(Nmt, StopSilencesSdoAndPdoButNotHeartbeat) {  // NMT-03, HB-04
  Harness h;
  h.boot();
  h.send("t00020132");
  h.send("t63282B171000E8030000");
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("t00020232"), "");
  EXPECT_EQ(h.send("t63284041600000000000"), "");
  h.set(0x6041, 0, 0x27);
  EXPECT_EQ(h.tick(3), "");
  EXPECT_EQ(h.run_until(t0 + 1000ms), "t732104\r");
  EXPECT_EQ(h.send("t00028032"), "");
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600027000000\r");
  EXPECT_EQ(h.run_until(t0 + 2000ms), "t73217F\r");
}

TEST(Nmt, EnterPreOperationalFromOperationalAndStopped) {  // NMT-04
  Harness h;
  h.boot();
  h.send("t00020132");
  h.send("t00028032");
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  h.send("t00020232");
  EXPECT_EQ(h.node->state(), NmtState::stopped);
  h.send("t00028000");
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  h.send("t00020232");
  h.send("t00020132");  // STOPPED → OPERATIONAL directly
  EXPECT_EQ(h.node->state(), NmtState::operational);
}

TEST(Nmt, ResetNodeCallsTheServerAndBootsAfter50ms) {  // NMT-05
  int resets = 0;
  Node::Hooks hooks;
  Harness* hp = nullptr;
  hooks.reset_node = [&] {
    ++resets;
    // the composition root rebuilds the OD: factory image + stored file (here: 1017h stored 500)
    reload_communication_objects(*hp->od, {}, std::vector<od::StoredValue>{{0x1017, 0, od::Value{std::int64_t{500}}}});
    hp->set(0x6041, 0, 0x40);
  };
  Harness h("MC349", {}, false, hooks);
  hp = &h;
  h.boot();
  h.send("t00020132");
  h.set(0x6041, 0, 0x27);
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));  // a transfer in progress ends silently
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("t00028132"), "");
  EXPECT_EQ(resets, 1);
  EXPECT_EQ(h.node->state(), NmtState::initialising);
  EXPECT_EQ(h.send("t63284041600000000000"), "");  // ignored meanwhile
  EXPECT_EQ(h.run_until(t0 + 49ms), "");
  EXPECT_EQ(h.run_until(t0 + 50ms), "t732100\r");
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  EXPECT_EQ(h.number(0x1017, 0), 500);
  EXPECT_EQ(h.run_until(t0 + 550ms), "t73217F\r");  // heartbeat period starts at the boot-up
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
}

// slcan-canopen.md §4.4: a reset that arrives while the node is still INITIALISING from an earlier
// one is executed, and the boot-up comes after the last one; other frames stay ignored.
TEST(Nmt, ResetWhileInitialisingIsExecuted) {  // NMT-09
  int node_resets = 0;
  int comm_resets = 0;
  Node::Hooks hooks;
  hooks.reset_node = [&] { ++node_resets; };
  hooks.reset_communication = [&] { ++comm_resets; };
  Harness h("MC349", {}, false, hooks);
  h.boot();
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("t00028132"), "");  // reset node
  EXPECT_EQ(h.run_until(t0 + 20ms), "");
  EXPECT_EQ(h.send("t00028100"), "");  // again, 20 ms later (all nodes)
  EXPECT_EQ(node_resets, 2) << "the second reset node is executed";
  EXPECT_EQ(h.run_until(t0 + 69ms), "") << "the first reset's boot-up (t0 + 50) does not come";
  EXPECT_EQ(h.run_until(t0 + 70ms), "t732100\r") << "50 ms after the last reset";
  EXPECT_EQ(h.wait(1s), "") << "one boot-up";

  const Millis t1 = h.now;
  EXPECT_EQ(h.send("t00028132"), "");  // reset node, then reset communication 5 ms later
  EXPECT_EQ(h.run_until(t1 + 5ms), "");
  EXPECT_EQ(h.send("t00020132"), "");  // a start while initialising: still ignored
  EXPECT_EQ(h.send("t00028133"), "");  // another node's reset: ignored
  EXPECT_EQ(h.send("t000182"), "");    // DLC 1: ignored
  EXPECT_EQ(comm_resets, 0);
  EXPECT_EQ(h.send("t00028232"), "");
  EXPECT_EQ(comm_resets, 1);
  EXPECT_EQ(h.run_until(t1 + 14ms), "");
  EXPECT_EQ(h.run_until(t1 + 15ms), "t732100\r") << "10 ms after the reset communication";
  EXPECT_EQ(h.node->state(), NmtState::pre_operational) << "the start was not remembered";

  h.node->power_on(h.now);  // power on's own boot-up delay: a reset inside it is executed too
  const Millis t2 = h.now;
  EXPECT_EQ(h.run_until(t2 + 5ms), "");
  EXPECT_EQ(h.send("t00028132"), "");
  EXPECT_EQ(node_resets, 4);
  EXPECT_EQ(h.run_until(t2 + 54ms), "");
  EXPECT_EQ(h.run_until(t2 + 55ms), "t732100\r");
}

TEST(Nmt, ResetCommunicationReloadsCommObjectsOnly) {  // NMT-06, HBG-06
  Harness h;
  h.boot();
  h.send("t00020132");
  h.send("t63282B171000E8030000");  // 1017h = 1000 (not stored)
  h.send("t63282B40600006000000");  // a drive object (not a comm object)
  const Millis t0 = h.now;
  EXPECT_EQ(h.send("t00028232"), "");
  EXPECT_EQ(h.run_until(t0 + 9ms), "");
  EXPECT_EQ(h.run_until(t0 + 10ms), "t732100\r");  // boot-up has no toggle and state 0 whatever 1017h held
  EXPECT_EQ(h.number(0x1017, 0), 0);               // reloaded from the factory image
  EXPECT_EQ(h.number(0x6040, 0), 6);               // untouched
  EXPECT_EQ(h.wait(5s), "");                       // no heartbeat any more
}

TEST(Nmt, ResetCommunicationUsesTheServerHook) {  // HB-05
  Node::Hooks hooks;
  Harness* hp = nullptr;
  hooks.reset_communication = [&] {
    reload_communication_objects(*hp->od, {}, std::vector<od::StoredValue>{{0x1017, 0, od::Value{std::int64_t{500}}}});
  };
  Harness h("MC349", {}, false, hooks);
  hp = &h;
  h.boot();
  const Millis t0 = h.now;
  h.send("t00028200");
  EXPECT_EQ(h.run_until(t0 + 10ms), "t732100\r");
  EXPECT_EQ(h.run_until(t0 + 509ms), "");
  EXPECT_EQ(h.run_until(t0 + 510ms), "t73217F\r");
  EXPECT_EQ(h.run_until(t0 + 1010ms), "t73217F\r");
}

TEST(Nmt, NodeIdZeroAddressesUsOtherNodesAreIgnored) {  // NMT-07
  Harness h;
  h.boot();
  h.send("t00020133");
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  h.send("t00020100");
  EXPECT_EQ(h.node->state(), NmtState::operational);
}

TEST(Nmt, MalformedCommandsAreIgnored) {  // NMT-08
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t000101"), "");
  EXPECT_EQ(h.send("t0003013200"), "");
  EXPECT_EQ(h.send("t00020332"), "");
  EXPECT_EQ(h.send("r0002"), "");
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
}

TEST(Nmt, NodeIdChangeAtResetCommunication) {  // OTH-09, EMCY-01
  Node::Hooks hooks;
  Harness* hp = nullptr;
  std::vector<od::StoredValue> stored;
  hooks.reset_communication = [&] { reload_communication_objects(*hp->od, {}, stored); };
  Harness h("MC349", {}, false, hooks);
  hp = &h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x40, 0x14, 0x10, 0x00})), resp({0x43, 0x14, 0x10, 0x00, 0xB2}));
  EXPECT_EQ(h.send(sdo({0x2F, 0x04, 0x34, 0x03, 5})), resp({0x60, 0x04, 0x34, 0x03}));
  EXPECT_EQ(h.node->node_id(), 50);  // takes effect only at the reset
  // a custom TPDO2 identifier (disable, change, enable)
  h.send(sdo({0x23, 0x01, 0x18, 0x01, 0xB2, 0x02, 0x00, 0x80}));
  h.send(sdo({0x23, 0x01, 0x18, 0x01, 0xC0, 0x01, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x23, 0x01, 0x18, 0x01, 0xC0, 0x01, 0x00, 0x00})), resp({0x60, 0x01, 0x18, 0x01}));
  // "store": what 1010h would have put in the file
  h.od->for_each([&](const od::EntryInfo& e, const od::Value& v) {
    if (e.cls == od::EntryClass::comm || (e.index == 0x3404 && e.sub == 3)) stored.push_back({e.index, e.sub, v});
  });
  const Millis t0 = h.now;
  h.send("t00028232");
  EXPECT_EQ(h.run_until(t0 + 10ms), "t705100\r");
  EXPECT_EQ(h.node->node_id(), 5);
  EXPECT_EQ(h.send("t63284041600000000000"), "");  // old SDO identifier
  EXPECT_EQ(h.send("t60584041600000000000"), "t58584B41600040000000\r");
  EXPECT_EQ(h.number(0x1014, 0), 0x85);
  EXPECT_EQ(h.number(0x1200, 1), 0x605);
  EXPECT_EQ(h.number(0x1200, 2), 0x585);
  EXPECT_EQ(h.number(0x1400, 1), 0x205);
  EXPECT_EQ(h.number(0x1800, 1), 0x185);
  EXPECT_EQ(h.number(0x1801, 1), 0x1C0);  // custom identifier kept
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(0ms), "t08582132050000000000\r");
  EXPECT_EQ(h.send("t00020105"), "t18524000\rt1C03400000\r");
}

TEST(Nmt, TimeLssAndExtendedFramesAreIgnored) {  // OTH-10
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t1006000000000000"), "");             // TIME
  EXPECT_EQ(h.send("t7E58" + std::string(16, '0')), "");  // LSS
  EXPECT_EQ(h.send("t7E48" + std::string(16, '0')), "");
  EXPECT_EQ(h.send("T0000063284041600000000000"), "");  // 29-bit with the SDO identifier
  EXPECT_EQ(h.send("T0000000020132"), "");              // 29-bit NMT
  EXPECT_EQ(h.node->state(), NmtState::pre_operational);
  EXPECT_EQ(h.send("t5B284B41600040000000"), "");  // our own transmit identifier
  EXPECT_EQ(h.send("t63384041600000000000"), "");  // another node's SDO
}

}  // namespace
}  // namespace mcemu::canopen::test
