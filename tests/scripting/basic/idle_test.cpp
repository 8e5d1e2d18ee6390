// Idle detection (interpreter.hpp): a program that polls an unchanging input is quiet, skip(n)
// leaves exactly the state n steps leave (checked against a twin stepped every ms), and programs
// that write, count or read time-dependent entries are never quiet.
#include <gtest/gtest.h>

#include <string>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

using test::Rig;

// A seven-statement wait loop with a subroutine (the GOSUB stack moves inside the cycle).
const char* k_waiting =
    ":L\n"
    "a = GETOBJ $2311.01\n"
    "IF a & 1 THEN GOTO Go\n"
    "GOSUB Sub\n"
    "b = 1\n"
    "GOTO L\n"
    ":Sub\n"
    "c = 2\n"
    "RETURN\n"
    ":Go\n"
    "SETOBJ $6040.00 = 6\n"
    "d = d + 1\n"
    ":M\n"
    "GOTO M\n";

TEST(BasicIdle, NotRunningIsQuietForever) {
  Rig rig;
  EXPECT_EQ(rig.interp->quiet_steps(), k_never);
  rig.start("a = 1\n");
  EXPECT_EQ(rig.interp->quiet_steps(), 0U);
  rig.step();
  EXPECT_EQ(rig.interp->quiet_steps(), k_never);
}

TEST(BasicIdle, AProgramWaitingOnAnInputBecomesQuiet) {
  Rig rig;
  rig.start(k_waiting);
  int steps = 0;
  while (rig.interp->quiet_steps() != k_never && steps < 20) {
    rig.step();
    ++steps;
  }
  EXPECT_LE(steps, 10) << "seven statements, 20 per step: the cycle is found within a few steps";
  EXPECT_TRUE(rig.interp->idle());
  rig.interp->skip(100000);
  rig.now += 100000;
  EXPECT_EQ(rig.interp->quiet_steps(), k_never);
  rig.set(0x2311, 0x01, 1);  // DigIn1: an object value changed
  EXPECT_EQ(rig.interp->quiet_steps(), 0U);
  rig.step();
  ASSERT_EQ(rig.of_kind(EventKind::setobj).size(), 1U);
  EXPECT_EQ(rig.od.number(0x6040, 0), 6);
  EXPECT_EQ(rig.var('d'), 1);
}

TEST(BasicIdle, ARepeatedWriteOfTheSameValueIsNotIdleWhenItIsASetobj) {
  Rig rig;
  rig.start(":L\nSETOBJ $6040.00 = 0\nGOTO L\n");
  for (int i = 0; i < 200; ++i) {
    rig.step();
    ASSERT_EQ(rig.interp->quiet_steps(), 0U) << "every SETOBJ is traced: skipping would lose them";
  }
}

TEST(BasicIdle, RunningTimersAndChangingVariablesKeepItBusy) {
  for (const char* busy : {"DEF_CYC_VAR c\nSTART_CYC\n:L\nGOTO L\n", ":L\na = a + 1\nGOTO L\n",
                           ":L\nFOR i = 1 TO 0\nNEXT\nGOTO L\n", "DEF_TIM_VAR t\nSTART_TIM 1000\n:L\nGOTO L\n"}) {
    Rig rig;
    rig.start(busy);
    for (int i = 0; i < 200; ++i) {
      rig.step();
      ASSERT_EQ(rig.interp->quiet_steps(), 0U) << busy << " step " << i;
    }
  }
}

TEST(BasicIdle, AnExpiredCountDownTimerIsQuiet) {
  Rig rig;
  rig.start("DEF_TIM_VAR t\nSTART_TIM 30\n:L\nIF t = 0 THEN GOTO L\nGOTO L\n");
  rig.step(30);
  EXPECT_EQ(rig.interp->quiet_steps(), 0U);
  rig.step(5);
  EXPECT_EQ(rig.interp->quiet_steps(), k_never);
}

TEST(BasicIdle, TimeDependentEntriesAndDisabledDetectionKeepItBusy) {
  Settings s;
  s.time_dependent = [](std::uint16_t index, std::uint8_t) { return index == 0x2311; };
  Rig rig(20, s);
  rig.start(k_waiting);
  rig.step(50);
  EXPECT_EQ(rig.interp->quiet_steps(), 0U);

  Settings off;
  off.idle_detection = false;
  Rig rig2(20, off);
  rig2.start(k_waiting);
  rig2.step(50);
  EXPECT_EQ(rig2.interp->quiet_steps(), 0U);
}

TEST(BasicIdle, AnOutsideWriteBetweenStepsEndsTheQuietStretch) {
  Rig rig;
  rig.start(":L\nIF i = 1 THEN GOTO Go\nGOTO L\n:Go\no = 2\n:M\nGOTO M\n");
  rig.step(5);
  ASSERT_EQ(rig.interp->quiet_steps(), k_never);
  rig.set_var('i', 1);
  EXPECT_EQ(rig.interp->quiet_steps(), 0U);
  rig.step();
  EXPECT_EQ(rig.var('o'), 2);
}

// Twin rigs: one stepped every ms, one skipping whenever it is quiet. At `t_input` both see the
// input; from then on their events, lines and statement counts must be identical.
void compare_with_twin(std::uint32_t per_ms, std::uint64_t t_input) {
  Rig full(per_ms), skipping(per_ms);
  full.start(k_waiting);
  skipping.start(k_waiting);
  while (full.now < t_input) full.step();
  std::uint64_t skipped = 0;
  while (skipping.now < t_input) {
    if (skipping.interp->quiet_steps() == k_never) {
      const std::uint64_t n = t_input - skipping.now;
      skipping.interp->skip(n);
      skipping.now += n;
      skipped += n;
    } else {
      skipping.step();
    }
  }
  EXPECT_GT(skipped, t_input / 2) << "the twin should have skipped most of the wait";
  EXPECT_EQ(full.interp->line(), skipping.interp->line()) << "N=" << per_ms << " t=" << t_input;
  EXPECT_EQ(full.interp->statements(), skipping.interp->statements());
  EXPECT_EQ(full.interp->gosub_depth(), skipping.interp->gosub_depth());
  full.set(0x2311, 0x01, 1);
  skipping.set(0x2311, 0x01, 1);
  for (int i = 0; i < 12; ++i) {  // N = 1: up to 9 statements to the SETOBJ
    full.step();
    skipping.step();
    ASSERT_EQ(full.interp->line(), skipping.interp->line()) << "N=" << per_ms << " t=" << t_input << " +" << i;
  }
  ASSERT_EQ(full.events.size(), skipping.events.size());
  for (std::size_t i = 0; i < full.events.size(); ++i) {
    EXPECT_EQ(describe(full.events[i]), describe(skipping.events[i]));
    EXPECT_EQ(full.events[i].time_ms, skipping.events[i].time_ms);
  }
  EXPECT_EQ(full.var('d'), 1);
  EXPECT_EQ(skipping.var('d'), 1);
}

TEST(BasicIdle, SkipLeavesExactlyTheStateOfTheSkippedSteps) {
  for (std::uint32_t n : {1U, 3U, 7U, 20U, 23U}) {
    for (std::uint64_t t : {100U, 101U, 102U, 103U, 104U, 105U, 106U, 1000U, 12345U}) compare_with_twin(n, t);
  }
}

}  // namespace
}  // namespace mcemu::basic
