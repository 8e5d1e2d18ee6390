// The CiA 402 rules (lint/cia402_rules.cpp): for each rule a sequence that triggers it and one that
// must not (docs/lint.md §4.1).
#include <gtest/gtest.h>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

constexpr std::uint16_t k_sod = 0x0040, k_rtso = 0x0021, k_so = 0x0023, k_oe = 0x0027, k_qsa = 0x0007, k_fault = 0x0008,
                        k_fra = 0x000F;

// ---- enable with a velocity target

TEST(Cia402EnableWithVelocityTarget, EnableInPvWithTargetFires) {
  Lint l;
  l.drive_at(0, k_so, 3);
  l.engine.observe(write(1, 0x60FF, 500, k_so, 3));
  l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 3));
  ASSERT_TRUE(l.only(RuleId::cia402_enable_with_velocity_target));
  EXPECT_EQ(l.found[0].time_ms, 2U);
  EXPECT_EQ(l.found[0].conn, 1U);
  EXPECT_EQ(l.found[0].origin, "sdo");
  EXPECT_NE(l.found[0].detail.find("60FFh = 500"), std::string::npos);
}

TEST(Cia402EnableWithVelocityTarget, TransitionThreePlusFourFromReadyFires) {
  Lint l;
  l.drive_at(0, k_rtso, 3);
  l.engine.observe(write(1, 0x60FF, -20, k_rtso, 3));
  l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 3));
  EXPECT_TRUE(l.only(RuleId::cia402_enable_with_velocity_target));
}

TEST(Cia402EnableWithVelocityTarget, ModeWrittenInTheSameStepFires) {
  // MovingCap: 6061h shows the new mode only after the next step; the enable still starts PV
  Lint l;
  l.drive_at(0, k_so, 1);
  l.engine.observe(write(1, 0x60FF, 500, k_so, 1));
  l.engine.observe(write(1, 0x6060, 3, k_so, 1));
  l.engine.observe(write(1, 0x6040, 0x000F, k_oe, 1));
  EXPECT_TRUE(l.only(RuleId::cia402_enable_with_velocity_target));
}

TEST(Cia402EnableWithVelocityTarget, QuietCases) {
  {  // target 0 at the enable, the target afterwards: the careful order
    Lint l;
    l.drive_at(0, k_so, 3);
    l.engine.observe(write(1, 0x60FF, 0, k_so, 3));
    l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 3));
    l.engine.observe(write(3, 0x60FF, 500, k_oe | 0x0100, 3));
    EXPECT_TRUE(l.found.empty());
  }
  {  // profile position: 60FFh does not move the axis
    Lint l;
    l.drive_at(0, k_so, 1);
    l.engine.observe(write(1, 0x60FF, 500, k_so, 1));
    l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 1));
    EXPECT_TRUE(l.found.empty());
  }
  {  // transition 16 out of quick stop is "continue", not a fresh enable
    Lint l;
    l.drive_at(0, k_oe, 3);
    l.engine.observe(write(1, 0x60FF, 500, k_oe, 3));
    l.engine.observe(write(2, 0x6040, 0x000B, k_qsa, 3));
    l.engine.observe(write(3, 0x6040, 0x000F, k_oe, 3));
    EXPECT_TRUE(l.found.empty());
  }
  {  // a helper's AUTOENABLE (GoVel writes the new target right after it)
    Lint l;
    l.drive_at(0, k_so, 3);
    l.engine.observe(write(1, 0x60FF, 500, k_so, 3));
    l.engine.observe(helper_write(write(2, 0x6040, 0x000F, k_oe, 3)));
    EXPECT_TRUE(l.found.empty());
  }
  {  // a refused 60FFh write leaves the target at 0
    Lint l;
    l.drive_at(0, k_so, 3);
    l.engine.observe(refused(write(1, 0x60FF, 500, k_so, 3)));
    l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 3));
    EXPECT_TRUE(l.found.empty());
  }
}

// ---- set-point before the acknowledge

TEST(Cia402SetpointBeforeAck, EdgeWhileBit12SetFires) {
  Lint l;
  l.drive_at(0, k_oe, 1);
  l.engine.observe(write(1, 0x6040, 0x000F, k_oe, 1));
  l.drive_at(2, k_oe | 0x1100, 1);  // buffer full: bit 12 stays set (drive-core.md §7.2 rule 3)
  l.engine.observe(write(3, 0x6040, 0x001F, k_oe | 0x1100, 1));
  EXPECT_TRUE(l.only(RuleId::cia402_setpoint_before_ack));
}

TEST(Cia402SetpointBeforeAck, QuietCases) {
  {  // bit 12 back to 0 before the next edge: the handshake done right
    Lint l;
    l.drive_at(0, k_oe, 1);
    l.engine.observe(write(1, 0x6040, 0x001F, k_oe | 0x1100, 1));
    l.engine.observe(write(2, 0x6040, 0x000F, k_oe | 0x0100, 1));
    l.engine.observe(write(3, 0x6040, 0x001F, k_oe | 0x1100, 1));
    EXPECT_TRUE(l.found.empty());
  }
  {  // change set immediately (bit 5)
    Lint l;
    l.drive_at(0, k_oe | 0x1100, 1);
    l.engine.observe(write(1, 0x6040, 0x003F, k_oe | 0x1100, 1));
    EXPECT_TRUE(l.found.empty());
  }
  {  // homing: bit 4 starts the method, no set-point handshake
    Lint l;
    l.drive_at(0, k_oe | 0x1000, 6);
    l.engine.observe(write(1, 0x6040, 0x001F, k_oe | 0x0100, 6));
    EXPECT_TRUE(l.found.empty());
  }
}

// ---- set-point without an edge

TEST(Cia402SetpointWithoutEdge, NewTargetWithBit4HeldFires) {
  Lint l;
  l.drive_at(0, k_oe, 1);
  l.engine.observe(write(1, 0x6040, 0x000F, k_oe, 1));
  l.engine.observe(write(2, 0x607A, 1000, k_oe, 1));
  l.engine.observe(write(3, 0x6040, 0x001F, k_oe | 0x1100, 1));
  l.engine.observe(write(4, 0x607A, 2000, k_oe | 0x0100, 1));
  l.engine.observe(write(5, 0x6040, 0x001F, k_oe | 0x0100, 1));
  ASSERT_TRUE(l.only(RuleId::cia402_setpoint_without_edge));
  EXPECT_EQ(l.found[0].time_ms, 5U);
}

TEST(Cia402SetpointWithoutEdge, QuietCases) {
  {  // bit 4 cleared, then set again
    Lint l;
    l.drive_at(0, k_oe, 1);
    l.engine.observe(write(1, 0x6040, 0x001F, k_oe | 0x1100, 1));
    l.engine.observe(write(2, 0x607A, 2000, k_oe | 0x1100, 1));
    l.engine.observe(write(3, 0x6040, 0x000F, k_oe | 0x0100, 1));
    l.engine.observe(write(4, 0x6040, 0x001F, k_oe | 0x1100, 1));
    EXPECT_TRUE(l.found.empty());
  }
  {  // the controlword written again with no new target in between
    Lint l;
    l.drive_at(0, k_oe, 1);
    l.engine.observe(write(1, 0x6040, 0x001F, k_oe | 0x1100, 1));
    l.engine.observe(write(2, 0x6040, 0x001F, k_oe | 0x1100, 1));
    EXPECT_TRUE(l.found.empty());
  }
}

// ---- mode change while moving

TEST(Cia402ModeChangeWhileMoving, SwitchWhileBit8Fires) {
  Lint l;
  l.engine.observe(PowerOn{0, 0x0000, 0, 3, 0});
  l.drive_at(1, k_oe | 0x0100, 3);
  l.engine.observe(write(2, 0x6060, 1, k_oe | 0x0100, 3));
  ASSERT_TRUE(l.only(RuleId::cia402_mode_change_while_moving));
  EXPECT_NE(l.found[0].detail.find("6060h := 1 (was 3)"), std::string::npos);
}

TEST(Cia402ModeChangeWhileMoving, QuietCases) {
  Lint l;
  l.engine.observe(PowerOn{0, 0x0000, 0, 3, 0});
  l.drive_at(1, k_oe, 3);
  l.engine.observe(write(2, 0x6060, 1, k_oe, 3));  // at standstill
  l.drive_at(3, k_oe | 0x0100, 1);
  l.engine.observe(write(4, 0x6060, 1, k_oe | 0x0100, 1));                // the same mode again
  l.engine.observe(helper_write(write(5, 0x6060, 3, k_oe | 0x0100, 1)));  // GoVel while a move runs
  l.engine.observe(refused(write(6, 0x6060, 7, k_oe | 0x0100, 3)));       // refused value
  EXPECT_TRUE(l.found.empty());
}

// ---- fault reset held

TEST(Cia402FaultResetHeld, Bit7KeptHighFires) {
  Lint l;
  l.drive_at(0, k_fault, 0);
  l.engine.observe(write(1, 0x6040, 0x0080, k_sod, 0));
  l.engine.observe(write(2, 0x6040, 0x0086, k_sod, 0));  // Shutdown with bit 7 still set: ignored
  ASSERT_TRUE(l.only(RuleId::cia402_fault_reset_held));
  EXPECT_EQ(l.found[0].time_ms, 2U);
}

TEST(Cia402FaultResetHeld, EdgesAreQuiet) {
  Lint l;
  l.drive_at(0, k_fault, 0);
  l.engine.observe(write(1, 0x6040, 0x0080, k_fault, 0));  // refused reset (cause present)
  l.engine.observe(write(2, 0x6040, 0x0000, k_fault, 0));
  l.engine.observe(write(3, 0x6040, 0x0080, k_sod, 0));
  l.engine.observe(write(4, 0x6040, 0x0006, k_rtso, 0));
  EXPECT_TRUE(l.found.empty());
}

// ---- command ignored (skipped states)

struct IgnoredCase {
  std::uint16_t before;
  std::uint16_t cw;
  std::uint16_t after;
  bool fires;
};

class Cia402CommandIgnored : public ::testing::TestWithParam<IgnoredCase> {};

TEST_P(Cia402CommandIgnored, Table) {
  const auto& c = GetParam();
  Lint l;
  l.drive_at(0, c.before, 1);
  l.engine.observe(write(1, 0x6040, c.cw, c.after, 1));
  if (c.fires) {
    EXPECT_TRUE(l.only(RuleId::cia402_command_ignored));
  } else {
    EXPECT_EQ(l.count(RuleId::cia402_command_ignored), 0U);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, Cia402CommandIgnored,
    ::testing::Values(IgnoredCase{k_sod, 0x000F, k_sod, true},      // enable from SOD (skips 2 and 3)
                      IgnoredCase{k_sod, 0x0007, k_sod, true},      // switch on from SOD
                      IgnoredCase{k_qsa, 0x0006, k_qsa, true},      // shutdown in QSA
                      IgnoredCase{k_qsa, 0x000F, k_qsa, true},      // enable in QSA with 605Ah 1/2
                      IgnoredCase{k_sod, 0x0006, k_rtso, false},    // transition 2
                      IgnoredCase{k_rtso, 0x000F, k_oe, false},     // 3+4
                      IgnoredCase{k_so, 0x000F, k_oe, false},       // 4
                      IgnoredCase{k_sod, 0x0000, k_sod, false},     // stays (disable voltage)
                      IgnoredCase{k_sod, 0x0002, k_sod, false},     // quick stop in SOD: harmless
                      IgnoredCase{k_rtso, 0x0006, k_rtso, false},   // stays
                      IgnoredCase{k_so, 0x0007, k_so, false},       // stays
                      IgnoredCase{k_oe, 0x0007, k_oe, false},       // transition 5 waits for its ramp
                      IgnoredCase{k_qsa, 0x000F, k_oe, false},      // transition 16
                      IgnoredCase{k_rtso, 0x0007, k_fault, false},  // switch-on refused by an enable check
                      IgnoredCase{k_fault, 0x0006, k_fault, false}  // Fault: motion_in_fault's business
                      ));

TEST(Cia402CommandIgnoredHelper, HelperWritesAreNotJudged) {
  Lint l;
  l.drive_at(0, k_sod, 1);
  l.engine.observe(helper_write(write(1, 0x6040, 0x000F, k_sod, 1)));
  EXPECT_TRUE(l.found.empty());
}

// ---- motion in fault

TEST(Cia402MotionInFault, EnableOperationInFaultFires) {
  Lint l;
  l.drive_at(0, k_fault, 1);
  l.engine.observe(write(1, 0x6040, 0x001F, k_fault, 1));
  EXPECT_TRUE(l.only(RuleId::cia402_motion_in_fault));
}

TEST(Cia402MotionInFault, HelperTargetInFaultReactionFires) {
  Lint l;
  l.drive_at(0, k_fra, 1);
  l.engine.observe(helper_write(write(1, 0x607A, 1000, k_fra, 1, od::Origin::refgo)));
  ASSERT_TRUE(l.only(RuleId::cia402_motion_in_fault));
  EXPECT_EQ(l.found[0].origin, "refgo");
}

TEST(Cia402MotionInFault, QuietCases) {
  Lint l;
  l.drive_at(0, k_fault, 1);
  l.engine.observe(write(1, 0x607A, 1000, k_fault, 1));  // a master preparing its next target
  l.engine.observe(write(2, 0x6040, 0x0080, k_sod, 1));  // the reset
  l.engine.observe(write(3, 0x6040, 0x0006, k_rtso, 1));
  l.engine.observe(write(4, 0x6040, 0x000F, k_oe, 1));
  l.engine.observe(helper_write(write(5, 0x60FF, 0, k_oe, 1)));
  EXPECT_TRUE(l.found.empty());
}

// ---- quick stop left active

TEST(Cia402QuickStopLeftActive, SetpointWithQuickStopStillCommandedFires) {
  Lint l;
  l.drive_at(0, k_oe, 1);
  l.engine.observe(write(1, 0x6040, 0x000B, k_qsa, 1));  // quick stop
  l.engine.observe(write(2, 0x6040, 0x001B, k_qsa, 1));  // a set-point, bit 2 still 0
  EXPECT_TRUE(l.only(RuleId::cia402_quick_stop_left_active));
}

TEST(Cia402QuickStopLeftActive, LeavingQuickStopFirstIsQuiet) {
  Lint l;
  l.drive_at(0, k_oe, 1);
  l.engine.observe(write(1, 0x6040, 0x000B, k_qsa, 1));
  l.engine.observe(write(2, 0x6040, 0x000F, k_oe, 1));  // transition 16
  l.engine.observe(write(3, 0x6040, 0x001F, k_oe | 0x1100, 1));
  EXPECT_TRUE(l.found.empty());
}

// ---- the origin internal and refused writes are never judged

TEST(Cia402, InternalAndRefusedWritesAreQuiet) {
  Lint l;
  l.drive_at(0, k_sod, 1);
  l.engine.observe(write(1, 0x6040, 0x000F, k_sod, 1, od::Origin::internal));
  l.engine.observe(refused(write(2, 0x6040, 0x000F, k_sod, 1), od::AbortCode::length_too_high));
  EXPECT_TRUE(l.found.empty());
}

}  // namespace
}  // namespace mcemu::lint::test
