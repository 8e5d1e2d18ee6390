// EMCY producer (slcan-canopen.md §7; conformance EMCY-01, EMCY-04 … EMCY-06) and the order of
// frames within one processing call (§2).
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

TEST(Emcy, FramesOfTheSpec) {  // §7.4
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x40, 0x14, 0x10, 0x00})), resp({0x43, 0x14, 0x10, 0x00, 0xB2}));  // EMCY-01
  h.node->emit_emcy(0x3221, 0x05);
  h.node->emit_emcy(0x4210, 0x09);
  h.node->emit_emcy(0x7121, 0x10);
  h.node->emit_emcy(0x8130, 0x10);
  h.node->emit_emcy(0x0000, 0x00);
  h.node->emit_emcy(0x509B, 0x00, {3, 0, 0, 0, 0});  // script SendEmcyMsg(3)
  EXPECT_EQ(h.wait(0ms),
            "t0B282132050000000000\rt0B281042090000000000\rt0B282171100000000000\r"
            "t0B283081100000000000\rt0B280000000000000000\rt0B289B50000300000000\r");
}

TEST(Emcy, WakesTheServerOutsideACall) {
  int wakes = 0;
  Node::Hooks hooks;
  hooks.wake = [&] { ++wakes; };
  Harness h("MC349", {}, false, hooks);
  h.boot();
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(wakes, 1);
  ASSERT_TRUE(h.node->next_deadline());
  EXPECT_LE(*h.node->next_deadline(), h.now);
}

TEST(Emcy, DisabledByBit31) {  // EMCY-04
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB2, 0x00, 0x00, 0x80})), resp({0x60, 0x14, 0x10, 0x00}));
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(0ms), "");
  h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB2, 0x00, 0x00, 0x00}));
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(0ms), "t0B282132050000000000\r");
}

TEST(Emcy, IdentifierRules) {  // EMCY-05
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB3})), abort_line(0x1014, 0, 0x06090030));
  h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB2, 0x00, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB3, 0x00, 0x00, 0x80})), resp({0x60, 0x14, 0x10, 0x00}));
  EXPECT_EQ(h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB3})), resp({0x60, 0x14, 0x10, 0x00}));
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(0ms), "t0B382132050000000000\r");
  h.send(sdo({0x23, 0x14, 0x10, 0x00, 0xB3, 0x00, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x23, 0x14, 0x10, 0x00, 0x7F})), abort_line(0x1014, 0, 0x06090030));
}

TEST(Emcy, NotSentAndNotQueuedWhileStoppedOrInitialising) {  // EMCY-06
  Harness h;
  h.boot();
  h.send("t00020232");
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(0ms), "");
  h.send("t00028032");
  EXPECT_EQ(h.wait(100ms), "");  // not later either
  h.send("t00028232");
  h.node->emit_emcy(0x3221, 0x05);
  EXPECT_EQ(h.wait(10ms), "t732100\r");
  h.send("t00020132");
  h.node->emit_emcy(0x3221, 0x05);  // OPERATIONAL: sent
  EXPECT_EQ(h.wait(0ms), "t0B282132050000000000\r");
}

TEST(Emcy, OrderWithinOneCall) {  // §2: SDO response, error control, EMCY, TPDOs, heartbeat
  Node::Hooks hooks;
  Harness* hp = nullptr;
  std::vector<std::pair<std::uint16_t, std::uint8_t>> core_events;
  hooks.after_od_write = [&] {  // what the server does: drain the core's events after each write
    for (auto [code, reg] : std::exchange(core_events, {})) hp->node->emit_emcy(code, reg);
  };
  Harness h("MC349", {}, false, hooks);
  hp = &h;
  h.od->on_write(0x6040, 0, [&](od::WriteRequest& req) {  // a controlword that makes the core fault
    if (std::get<std::int64_t>(req.value) == 0x0F) {
      h.od->write(0x6041, 0, od::Value{std::int64_t{0x08}}, od::Origin::internal);
      core_events.emplace_back(0xFFF2, 0x10);
    }
    return od::AbortCode::none;
  });
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("t63282B4060000F000000"), "t5B286040600000000000\rt0B28F2FF100000000000\rt1B220800\rt2B23080000\r");
  // an RPDO write does the same
  h.od->write(0x6041, 0, od::Value{std::int64_t{0x40}}, od::Origin::internal);
  h.tick(1);
  EXPECT_EQ(h.send("t23220F00"), "t0B28F2FF100000000000\rt1B220800\rt2B23080000\r");
}

}  // namespace
}  // namespace mcemu::canopen::test
