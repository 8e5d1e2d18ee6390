// Events on the device status word (faulhaber.md §9.6) and the two timers (§9.7) against simulated
// time: edge triggering, replacement, the RET_EVT return point, DEF_EVT_VAR's value, no nesting,
// DI_EVT; count-down and count-up timers, master writes to a timer variable, skipped time.
#include <gtest/gtest.h>

#include <string>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

using test::Rig;

void status(Rig& rig, std::uint32_t v) { rig.set(k_status_index, k_status_sub, v); }

const char* k_counting =
    "DEF_EVT_VAR e\n"
    "EN_EVT $10, H\n"
    ":L\n"
    "a = a + 1\n"
    "GOTO L\n"
    ":H\n"
    "h = h + 1\n"
    "RET_EVT\n";

TEST(BasicEvents, AHandlerRunsOncePerRisingEdge) {
  Rig rig;
  rig.start(k_counting);
  rig.step(3);
  EXPECT_EQ(rig.var('h'), 0);
  status(rig, 0x20);  // a bit outside the mask
  rig.step(3);
  EXPECT_EQ(rig.var('h'), 0);
  status(rig, 0x30);
  rig.step();
  EXPECT_EQ(rig.var('h'), 1);
  EXPECT_EQ(rig.var('e'), 0x30) << "DEF_EVT_VAR gets the whole status word";
  rig.step(20);  // the level persists: no second call
  EXPECT_EQ(rig.var('h'), 1);
  status(rig, 0);
  rig.step();
  status(rig, 0x10);
  rig.step();
  EXPECT_EQ(rig.var('h'), 2);
  EXPECT_TRUE(rig.interp->running());
}

TEST(BasicEvents, AConditionPresentAtRegistrationIsNoEdge) {
  Rig rig;
  status(rig, 0x10);
  rig.start(k_counting);
  rig.step(5);
  EXPECT_EQ(rig.var('h'), 0);
  status(rig, 0);
  rig.step();
  status(rig, 0x10);
  rig.step();
  EXPECT_EQ(rig.var('h'), 1);
}

TEST(BasicEvents, DefEvtVarGetsTheFullStatusWordAsSigned) {
  Rig rig;
  rig.start("DEF_EVT_VAR e\nEN_EVT $00010000, OverTemp\n:L\nGOTO L\n:OverTemp\nh = 1\nRET_EVT\n");
  rig.step();
  status(rig, 0x80010010);
  rig.step();
  EXPECT_EQ(rig.var('h'), 1);
  EXPECT_EQ(rig.var('e'), static_cast<std::int32_t>(0x80010010U));
}

TEST(BasicEvents, ANewEnEvtReplacesTheHandler) {
  Rig rig;
  rig.start(
      "EN_EVT $1, H1\n"
      "EN_EVT $2, H2\n"
      ":L\nGOTO L\n"
      ":H1\nf = f + 1\nRET_EVT\n"
      ":H2\ng = g + 1\nRET_EVT\n");
  rig.step();
  status(rig, 1);
  rig.step(2);
  EXPECT_EQ(rig.var('f'), 0);
  EXPECT_EQ(rig.var('g'), 0);
  status(rig, 3);
  rig.step(2);
  EXPECT_EQ(rig.var('f'), 0);
  EXPECT_EQ(rig.var('g'), 1);
}

TEST(BasicEvents, RetEvtReturnsToTheStatementThatWasAboutToRun) {
  Rig rig(1);  // one statement per step
  rig.start(
      "EN_EVT $1, H\n"  // 1
      ":L\n"            // 2
      "a = a + 1\n"     // 3
      "b = b + 1\n"     // 4
      "c = c + 1\n"     // 5
      "GOTO L\n"        // 6
      ":H\n"            // 7
      "h = h + 1\n"     // 8
      "RET_EVT\n");     // 9
  rig.step(2);          // EN_EVT, a = a + 1
  ASSERT_EQ(rig.interp->line(), 4U);
  status(rig, 1);
  rig.step();  // the check before line 4 calls the handler; its first statement runs
  EXPECT_EQ(rig.var('h'), 1);
  EXPECT_EQ(rig.var('b'), 0);
  EXPECT_EQ(rig.interp->line(), 9U);
  EXPECT_EQ(rig.interp->gosub_depth(), 1U);
  rig.step();  // RET_EVT
  EXPECT_EQ(rig.interp->line(), 4U);
  EXPECT_EQ(rig.interp->gosub_depth(), 0U);
  rig.step();
  EXPECT_EQ(rig.var('a'), 1);
  EXPECT_EQ(rig.var('b'), 1);
  EXPECT_EQ(rig.var('c'), 0);
}

TEST(BasicEvents, EventsDoNotNestAndAnEdgeDuringTheHandlerComesAfterRetEvt) {
  Rig rig(1);
  rig.start(
      "EN_EVT $1, H\n"  // 1
      ":L\n"            // 2
      "GOTO L\n"        // 3
      ":H\n"            // 4
      "h = h + 1\n"     // 5
      "w = w + 1\n"     // 6
      "w = w + 1\n"     // 7
      "RET_EVT\n");     // 8
  rig.step();
  status(rig, 1);
  rig.step();  // handler: h = 1
  EXPECT_EQ(rig.var('h'), 1);
  status(rig, 0);
  rig.step();  // w = 1
  status(rig, 1);
  rig.step();  // w = 2; the edge is noted, the handler is not re-entered
  EXPECT_EQ(rig.var('h'), 1);
  EXPECT_EQ(rig.var('w'), 2);
  EXPECT_EQ(rig.interp->gosub_depth(), 1U);
  rig.step();  // RET_EVT
  rig.step();  // the noted edge: the handler again
  EXPECT_EQ(rig.var('h'), 2);
}

TEST(BasicEvents, DiEvtDisablesTheHandler) {
  Rig rig;
  rig.start("EN_EVT $1, H\nDI_EVT\n:L\nGOTO L\n:H\nh = 1\nRET_EVT\n");
  rig.step();
  status(rig, 1);
  rig.step(3);
  EXPECT_EQ(rig.var('h'), 0);
}

TEST(BasicEvents, ReturnInsideAHandlerIsAnError) {
  Rig rig;
  rig.start("EN_EVT $1, H\n:L\nGOTO L\n:H\nRETURN\n");
  rig.step();
  status(rig, 1);
  rig.step();
  ASSERT_EQ(rig.interp->state(), RunState::error);
  EXPECT_EQ(rig.interp->error().line, 5U);
}

TEST(BasicEvents, AHandlerMayGosubAndRetEvtUnwinds) {
  Rig rig;
  rig.start("EN_EVT $1, H\n:L\nGOTO L\n:H\nGOSUB S\nh = 1\n:S\nRET_EVT\n");
  rig.step();
  status(rig, 1);
  rig.step();
  EXPECT_TRUE(rig.interp->running());
  EXPECT_EQ(rig.interp->gosub_depth(), 0U);
  EXPECT_EQ(rig.var('h'), 0);
}

TEST(BasicTimers, CountDownInDriveTime) {
  Rig rig;
  rig.start("DEF_TIM_VAR t\nSTART_TIM 100\n:L\nx = t\nGOTO L\n");
  rig.step();  // ms 1: started at 100
  EXPECT_EQ(rig.var('t'), 100);
  EXPECT_EQ(rig.var('x'), 100);
  rig.step();  // timers advance before the statements of a step
  EXPECT_EQ(rig.var('t'), 99);
  EXPECT_EQ(rig.var('x'), 99);
  rig.step(98);
  EXPECT_EQ(rig.var('t'), 1);
  rig.step();
  EXPECT_EQ(rig.var('t'), 0);
  rig.step(50);
  EXPECT_EQ(rig.var('t'), 0);
  rig.set_var('t', 30);  // a master write: counting continues from there
  rig.step();
  EXPECT_EQ(rig.var('t'), 29);
  rig.now += 9;  // ten ms pass before the next step (a skipped quiet stretch)
  rig.step();
  EXPECT_EQ(rig.var('t'), 19);
}

TEST(BasicTimers, NegativeStartIsZero) {
  Rig rig;
  rig.start("DEF_TIM_VAR t\nt = 5\nSTART_TIM -5\n");
  rig.step();
  EXPECT_EQ(rig.var('t'), 0);
}

TEST(BasicTimers, CountUpAndStop) {
  Rig rig;
  rig.set_var('c', 777);
  rig.start(
      "DEF_CYC_VAR c\n"
      "START_CYC\n"
      ":L\n"
      "IF c >= 50 THEN GOTO Halt\n"
      "GOTO L\n"
      ":Halt\n"
      "STOP_CYC\n"
      "x = c\n"
      ":M\n"
      "GOTO M\n");
  rig.step();
  EXPECT_EQ(rig.var('c'), 0);
  rig.step(10);
  EXPECT_EQ(rig.var('c'), 10);
  rig.step(40);
  EXPECT_EQ(rig.var('x'), 50);
  rig.step(30);
  EXPECT_EQ(rig.var('c'), 50) << "STOP_CYC freezes the variable";
}

TEST(BasicTimers, BothTimersRunTogether) {
  Rig rig;
  rig.start("DEF_TIM_VAR t\nDEF_CYC_VAR c\nSTART_TIM 20\nSTART_CYC\n:L\nGOTO L\n");
  rig.step(11);
  EXPECT_EQ(rig.var('t'), 10);
  EXPECT_EQ(rig.var('c'), 10);
}

TEST(BasicTimers, StoppedProgramsDoNotCount) {
  Rig rig;
  rig.start("DEF_CYC_VAR c\nSTART_CYC\n:L\nGOTO L\n");
  rig.step(5);
  rig.interp->stop();
  rig.step(5);
  EXPECT_EQ(rig.var('c'), 4);
}

}  // namespace
}  // namespace mcemu::basic
