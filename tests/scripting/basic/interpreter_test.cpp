// The executor (faulhaber.md §9.3, §9.5, §9.8, §9.9): statements, IF forms, GOSUB/RETURN, FOR,
// SETOBJ conversion, run-time errors with line and abort code, SAVE/LOAD, the variables shared with
// the dictionary, and the statements-per-step bound.
#include "scripting/basic/interpreter.hpp"

#include <gtest/gtest.h>

#include <string>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

using test::Rig;

TEST(BasicRun, AssignmentsRunInOrderAndTheEndStopsNormally) {
  Rig rig;
  rig.start("a = 1\nb = a + 1\n' c\n\nc = b * 10\n");
  rig.step();
  EXPECT_EQ(rig.interp->state(), RunState::finished);
  EXPECT_EQ(rig.var('a'), 1);
  EXPECT_EQ(rig.var('b'), 2);
  EXPECT_EQ(rig.var('c'), 20);
  ASSERT_EQ(rig.events.size(), 2U);
  EXPECT_EQ(rig.events[0].kind, EventKind::started);
  EXPECT_EQ(rig.events[1].kind, EventKind::finished);
}

TEST(BasicRun, BlockIfTakesTheFirstTrueBranch) {
  for (int y = 0; y < 4; ++y) {
    Rig rig;
    rig.set_var('y', y);
    rig.start("IF(y = 0) THEN\nr = 10\nELSEIF(y = 1) THEN\nr = 11\nELSEIF (y = 2) THEN\nr = 12\nELSE\nr = 13\nENDIF\n");
    rig.step();
    EXPECT_EQ(rig.var('r'), 10 + y) << y;
  }
}

TEST(BasicRun, OneLineIfAndTheBlockItOpens) {
  Rig rig;
  rig.start(
      "a = 1\n"
      "IF a = 1 THEN b = 1\n"
      "IF a = 2 THEN c = 1\n"
      "IF (a = 2) THEN d = 1\n"
      "ELSEIF(a = 1) THEN d = 2\n"
      "ELSE d = 3\n"
      "ENDIF\n"
      "IF a = 7 THEN e = 1\n"
      "ELSE e = 2\n"
      "ENDIF\n");
  rig.step();
  EXPECT_EQ(rig.var('b'), 1);
  EXPECT_EQ(rig.var('c'), 0);
  EXPECT_EQ(rig.var('d'), 2);
  EXPECT_EQ(rig.var('e'), 2);
}

TEST(BasicRun, NestedBlocksAndGotoInsideABranch) {
  Rig rig;
  rig.start(
      "IF 1 THEN\n"
      "  :Again\n"
      "  n = n + 1\n"
      "  IF n < 5 THEN GOTO Again\n"
      "  IF n = 5 THEN\n"
      "    IF 0 THEN\n"
      "      r = 1\n"
      "    ELSE\n"
      "      r = 2\n"
      "    ENDIF\n"
      "  ENDIF\n"
      "ENDIF\n");
  rig.run_to_end();
  EXPECT_EQ(rig.var('n'), 5);
  EXPECT_EQ(rig.var('r'), 2);
}

TEST(BasicRun, GosubReturnsIntoTheBlockItWasCalledFrom) {
  Rig rig;
  rig.start(
      "IF 1 THEN\n"
      "  GOSUB Sub\n"
      "  b = a + 1\n"
      "ENDIF\n"
      "IF 1 THEN GOSUB Sub\n"
      "c = a\n"
      "GOTO End\n"
      ":Sub\n"
      "a = a + 10\n"
      "Return\n"
      ":End\n");
  rig.run_to_end();
  EXPECT_EQ(rig.interp->state(), RunState::finished);
  EXPECT_EQ(rig.var('b'), 11);
  EXPECT_EQ(rig.var('c'), 20);
  EXPECT_EQ(rig.interp->gosub_depth(), 0U);
}

TEST(BasicRun, GosubDepthSixteenWorksSeventeenIsAnError) {
  const std::string recurse =
      "GOSUB R\n"
      "GOTO End\n"
      ":R\n"
      "d = d + 1\n"
      "IF d < n THEN GOSUB R\n"
      "RETURN\n"
      ":End\n";
  {
    Rig rig;
    rig.set_var('n', 16);
    rig.start(recurse);
    rig.run_to_end();
    EXPECT_EQ(rig.interp->state(), RunState::finished) << rig.interp->error().message;
    EXPECT_EQ(rig.var('d'), 16);
  }
  {
    Rig rig;
    rig.set_var('n', 17);
    rig.start(recurse);
    rig.run_to_end();
    ASSERT_EQ(rig.interp->state(), RunState::error);
    EXPECT_EQ(rig.interp->error().line, 5U);
    EXPECT_NE(rig.interp->error().message.find("GOSUB nested deeper than 16"), std::string::npos);
    EXPECT_EQ(rig.var('d'), 16);
    EXPECT_EQ(rig.interp->gosub_depth(), 16U);
  }
}

TEST(BasicRun, EndlessRecursionStopsWithAnError) {
  Rig rig;
  rig.start(":R\nGOSUB R\n");
  rig.step();
  EXPECT_EQ(rig.interp->state(), RunState::error);
  EXPECT_EQ(rig.interp->error().line, 2U);
}

TEST(BasicRun, ForCountsUpDownAndSkipsAnEmptyRange) {
  struct Case {
    const char* head;
    std::int32_t passes;
    std::int32_t sum;
    std::int32_t after;
  };
  for (const Case& c : {Case{"FOR i = 1 TO 5", 5, 15, 6}, Case{"FOR i = 5 TO 1 STEP -2", 3, 9, -1},
                        Case{"FOR i = 5 TO 1", 0, 0, 5}, Case{"FOR i = 1 TO 5 STEP -1", 0, 0, 1},
                        Case{"FOR i = 3 TO 3", 1, 3, 4}, Case{"FOR i = -2 To 2 STEP 2", 3, 0, 4},
                        // ends although i + 1 wraps (the sum wraps too)
                        Case{"FOR i = 2147483645 TO 2147483647", 3, 2147483642, -2147483647 - 1},
                        Case{"for i = 10 to 1 step -4", 3, 18, -2}}) {
    Rig rig;
    rig.start(std::string(c.head) + "\n  p = p + 1\n  s = s + i\nNEXT i\n");
    rig.run_to_end();
    ASSERT_EQ(rig.interp->state(), RunState::finished) << c.head << ": " << rig.interp->error().message;
    EXPECT_EQ(rig.var('p'), c.passes) << c.head;
    EXPECT_EQ(rig.var('s'), c.sum) << c.head;
    EXPECT_EQ(rig.var('i'), c.after) << c.head;
  }
}

TEST(BasicRun, ForBoundsAreEvaluatedOnce) {
  Rig rig;
  rig.set_var('n', 3);
  rig.set_var('k', 1);
  rig.start("FOR i = 1 TO n STEP k\n  n = 10\n  k = 5\n  p = p + 1\nNEXT\n");
  rig.run_to_end();
  EXPECT_EQ(rig.var('p'), 3);
}

TEST(BasicRun, NestedForLoops) {
  Rig rig;
  rig.start("FOR i = 1 TO 3\n  FOR j = 1 TO 4\n    p = p + 1\n  NEXT j\nNEXT i\n");
  rig.run_to_end();
  EXPECT_EQ(rig.var('p'), 12);
}

TEST(BasicRun, NextOfALoopEnteredByGotoIsAnError) {
  Rig rig;
  rig.start("GOTO In\nFOR i = 1 TO 3\n:In\nNEXT\n");
  rig.step();
  ASSERT_EQ(rig.interp->state(), RunState::error);
  EXPECT_EQ(rig.interp->error().line, 4U);
}

TEST(BasicRun, SetobjConvertsToTheEntryTypeAndTracesEveryWrite) {
  Rig rig;
  rig.start(
      "SETOBJ $6040.00 = $1000F\n"  // UNSIGNED16: 0x000F
      "SETOBJ $6060.00 = 255\n"     // INTEGER8: -1
      "SETOBJ $2310.03 = $18000\n"  // INTEGER16: -32768
      "SETOBJ $6083.00 = -1\n"      // UNSIGNED32: 0xFFFFFFFF
      "SETOBJ $2310.$11 = -1\n"     // UNSIGNED8: 255
      "SETOBJ $2400.05 = 7\n"       // BOOLEAN: non-zero → 1
      "SETOBJ $607A.00 = -10000\n"
      "SETOBJ $3005.1A = 42\n");  // z through its object
  rig.step();
  EXPECT_EQ(rig.interp->state(), RunState::finished) << rig.interp->error().message;
  EXPECT_EQ(rig.od.number(0x6040, 0), 0x000F);
  EXPECT_EQ(rig.od.number(0x6060, 0), -1);
  EXPECT_EQ(rig.od.number(0x2310, 0x03), -32768);
  EXPECT_EQ(rig.od.number(0x6083, 0), 0xFFFFFFFFLL);
  EXPECT_EQ(rig.od.number(0x2310, 0x11), 255);
  EXPECT_EQ(rig.od.number(0x2400, 0x05), 1);
  EXPECT_EQ(rig.od.number(0x607A, 0), -10000);
  EXPECT_EQ(rig.var('z'), 42);
  const auto writes = rig.of_kind(EventKind::setobj);
  ASSERT_EQ(writes.size(), 8U);
  EXPECT_EQ(writes[0].index, 0x6040);
  EXPECT_EQ(writes[0].value, 0x000F);
  EXPECT_EQ(writes[0].line, 1U);
  EXPECT_EQ(describe(writes[1]), "setobj line 2 6060h.00 = -1");
}

TEST(BasicRun, SetobjWritesWithOriginScript) {
  Rig rig;
  std::vector<od::Origin> origins;
  rig.od.on_write(0x607A, 0, [&](od::WriteRequest& r) {
    origins.push_back(r.origin);
    return od::AbortCode::none;
  });
  rig.start("SETOBJ $607A.00 = 5\n");
  rig.step();
  EXPECT_EQ(origins, (std::vector<od::Origin>{od::Origin::script}));
}

struct RuntimeErrorCase {
  const char* name;
  const char* program;
  std::uint32_t line;
  const char* message_part;
  od::AbortCode code;
};

class BasicRuntimeErrors : public ::testing::TestWithParam<RuntimeErrorCase> {};

TEST_P(BasicRuntimeErrors, StopWithLineMessageAndCode) {
  const auto& c = GetParam();
  Rig rig;
  rig.start(c.program);
  rig.step(3);
  ASSERT_EQ(rig.interp->state(), RunState::error) << c.name;
  EXPECT_EQ(rig.interp->error().line, c.line) << c.name;
  EXPECT_NE(rig.interp->error().message.find(c.message_part), std::string::npos)
      << c.name << ": " << rig.interp->error().message;
  EXPECT_EQ(rig.interp->error().code, c.code) << c.name;
  EXPECT_FALSE(rig.interp->running());
  EXPECT_EQ(rig.of_kind(EventKind::error).size(), 1U);
}

const RuntimeErrorCase k_runtime_errors[] = {
    {"div0", "a = 1\nb = a / (a - 1)\n", 2, "division by zero", od::AbortCode::none},
    {"setobj_read_only", "a = 1\nSETOBJ $6041.00 = 1\n", 2, "SETOBJ 6041h.00 = 1: 06010002", od::AbortCode::read_only},
    {"setobj_limit", "SETOBJ $2310.04 = 9\n", 1, "06090031", od::AbortCode::value_too_high},
    {"setobj_no_object", "SETOBJ $1234.00 = 1\n", 1, "06020000", od::AbortCode::no_object},
    {"setobj_string", "SETOBJ $1008.00 = 1\n", 1, "06010002", od::AbortCode::read_only},
    {"getobj_no_sub", "a = GETOBJ $6040.01\n", 1, "06090011", od::AbortCode::no_sub},
    {"return_without_gosub", "a = 1\nRETURN\n", 2, "RETURN without GOSUB", od::AbortCode::none},
    {"ret_evt_outside", "RET_EVT\n", 1, "RET_EVT outside an event handler", od::AbortCode::none},
    {"start_tim_before_def", "START_TIM 100\n", 1, "START_TIM before DEF_TIM_VAR", od::AbortCode::none},
    {"start_cyc_before_def", "DEF_TIM_VAR t\nSTART_CYC\n", 2, "START_CYC before DEF_CYC_VAR", od::AbortCode::none},
    {"stop_cyc_before_def", "STOP_CYC\n", 1, "STOP_CYC before DEF_CYC_VAR", od::AbortCode::none},
    {"en_evt_in_expression", "EN_EVT 1 / 0, H\n:H\n", 1, "division by zero", od::AbortCode::none},
};

INSTANTIATE_TEST_SUITE_P(Table, BasicRuntimeErrors, ::testing::ValuesIn(k_runtime_errors));

TEST(BasicRun, AMissingVariableEntryIsAnErrorWithItsCode) {
  auto entries = test::dictionary_entries();
  std::erase_if(entries, [](const od::EntryInfo& e) { return e.index == 0x3005 && e.sub == 3; });
  od::ObjectDictionary od(std::move(entries));
  MemoryVariables store;
  Interpreter interp(od, store);
  const Program p = test::must_load("a = 1\nc = 2\n");
  interp.start(p);
  interp.step(1);
  ASSERT_EQ(interp.state(), RunState::error);
  EXPECT_EQ(interp.error().line, 2U);
  EXPECT_EQ(interp.error().code, od::AbortCode::no_sub);
  EXPECT_NE(interp.error().message.find("c (3005h.03)"), std::string::npos) << interp.error().message;
}

TEST(BasicRun, SaveAndLoadGoThroughTheStoreAndAreCounted) {
  Rig rig;
  rig.set_var('a', 7);
  rig.set_var('b', -3);
  rig.start("SAVE a, b\na = 0\nb = 0\nc = 99\nLOAD a, b, c\nSAVE c\n");
  rig.step();
  ASSERT_EQ(rig.interp->state(), RunState::finished) << rig.interp->error().message;
  EXPECT_EQ(rig.var('a'), 7);
  EXPECT_EQ(rig.var('b'), -3);
  EXPECT_EQ(rig.var('c'), 0) << "LOAD of a variable never saved gives 0";
  EXPECT_EQ(rig.store.saves(), 2U);
  EXPECT_EQ(rig.interp->save_count(), 2U);
  const auto saves = rig.of_kind(EventKind::save);
  ASSERT_EQ(saves.size(), 2U);
  EXPECT_EQ(saves[0].saved, (std::vector<SavedVariable>{{0, 7}, {1, -3}}));
  EXPECT_EQ(saves[0].line, 1U);
  EXPECT_EQ(saves[1].save_count, 2U);
  EXPECT_EQ(describe(saves[0]), "save line 1 a=7 b=-3 (#1)");
}

TEST(BasicRun, SavedVariablesSurviveAPowerCycle) {
  MemoryVariables store;  // the owner's durable store outlives the drive's RAM
  {
    od::ObjectDictionary od(test::dictionary_entries());
    Interpreter interp(od, store);
    const Program p = test::must_load("k = 1234\nSAVE k\n");
    interp.start(p);
    interp.step(1);
  }
  od::ObjectDictionary od(test::dictionary_entries());  // power on: variables are 0
  ASSERT_EQ(od.number(0x3005, 11), 0);
  Interpreter interp(od, store);
  const Program p = test::must_load("LOAD k\n");
  interp.start(p);
  interp.step(1);
  EXPECT_EQ(od.number(0x3005, 11), 1234);
}

TEST(BasicRun, AMasterWriteBetweenStepsIsSeenByTheNextStatement) {
  Rig rig(1);  // one statement per step
  rig.start(
      ":Wait\n"
      "IF i = 1 THEN GOTO Go\n"
      "GOTO Wait\n"
      ":Go\n"
      "o = 2\n");
  rig.step(4);  // IF, GOTO, IF, GOTO
  EXPECT_EQ(rig.var('o'), 0);
  ASSERT_EQ(rig.interp->line(), 2U);  // the IF is next
  rig.set_var('i', 1);                // 0x3005.09 over the protocol (origin sdo)
  rig.step();                         // the IF sees it
  EXPECT_EQ(rig.interp->line(), 5U);
  rig.step();
  EXPECT_EQ(rig.var('o'), 2);
}

TEST(BasicRun, VariablesKeepTheirValuesAcrossStartAndStop) {
  Rig rig;
  rig.set_var('i', 5);
  rig.start("o = i + 1\n:L\nGOTO L\n");
  rig.step();
  rig.interp->stop();
  EXPECT_EQ(rig.interp->state(), RunState::stopped);
  EXPECT_EQ(rig.var('o'), 6);
  EXPECT_EQ(rig.var('i'), 5);
  EXPECT_EQ(rig.events.back().kind, EventKind::stopped);
  EXPECT_EQ(describe(rig.events.back()), "stop slot 1 (stop request)");
}

// Every program, however it loops, runs at most N statements per step.
TEST(BasicRun, TheStatementsPerStepBoundHolds) {
  for (const char* program :
       {":L\nGOTO L\n", ":L\na = a + 1\nGOTO L\n", ":L\nIF 1 THEN GOTO L\n", "FOR i = 1 TO 2 STEP 0\nNEXT\n",
        ":S\nGOSUB T\nGOTO S\n:T\nRETURN\n", "IF 1 THEN\n:L\na = a + 1\nIF 1 THEN GOTO L\nENDIF\n"}) {
    for (std::uint32_t n : {1U, 7U, 20U}) {
      Rig rig(n);
      rig.start(program);
      for (int s = 0; s < 50; ++s) {
        const auto before = rig.interp->statements();
        rig.step();
        ASSERT_TRUE(rig.interp->running()) << program;
        EXPECT_EQ(rig.interp->statements() - before, n) << program << " N=" << n;
      }
    }
  }
}

TEST(BasicRun, LabelsCommentsElseAndEndifCostNothing) {
  Rig rig(4);
  rig.start(":A\n' x\n\na = 1\nIF a THEN\nb = 1\nELSE\nb = 2\nENDIF\n:B\nc = 1\n:L\nGOTO L\n");
  rig.step();  // a = 1, IF, b = 1, c = 1
  EXPECT_EQ(rig.var('c'), 1);
  EXPECT_EQ(rig.interp->statements(), 4U);
  EXPECT_EQ(rig.interp->line(), 13U);
}

TEST(BasicRun, AnEmptyProgramEndsAtOnceAndZeroStatementsPerMsMeansOne) {
  Rig rig;
  const Program none;  // not from load(): no instructions at all
  rig.interp->start(none);
  EXPECT_EQ(rig.interp->state(), RunState::finished);
  rig.start("");
  rig.step();
  EXPECT_EQ(rig.interp->state(), RunState::finished);

  Rig zero(0);
  zero.start(":L\nGOTO L\n");
  zero.step(10);
  EXPECT_EQ(zero.interp->statements(), 10U);
}

TEST(BasicRun, ErrorEventsDescribeSlotLineAndReason) {
  Rig rig;
  rig.start("a = 1\nb = a / 0\n");
  rig.step();
  EXPECT_EQ(describe(rig.events.back()), "error slot 1 line 2: division by zero");
  rig.start("SETOBJ $6041.00 = 3\n");
  rig.step();
  const auto w = rig.of_kind(EventKind::setobj);
  ASSERT_EQ(w.size(), 1U);
  EXPECT_EQ(describe(w[0]), "setobj line 1 6041h.00 = 3 refused 06010002");
}

// The master lint's script.busy_loop: statements since the program last waited. A loop that only
// computes never waits; a GETOBJ, a read of its timer variable and an event check are waits; a start
// resets the count.
struct WaitCase {
  const char* name;
  const char* program;
  std::uint64_t at_most;  // statements_since_wait() after 10 steps of 20 statements
};

class BasicWaits : public ::testing::TestWithParam<WaitCase> {};

TEST_P(BasicWaits, StatementsSinceTheLastWait) {
  Rig rig;
  rig.interp->set_statements_per_ms(20);
  rig.start(GetParam().program);
  rig.step(10);
  ASSERT_TRUE(rig.interp->running());
  EXPECT_LE(rig.interp->statements_since_wait(), GetParam().at_most) << GetParam().name;
}

const WaitCase k_waits[] = {
    {"busy", ":l\na = a + 1\nGOTO l\n", 200},
    {"getobj", ":l\na = GETOBJ $6041.00\nb = b + 1\nGOTO l\n", 3},
    {"timer", "DEF_TIM_VAR t\nSTART_TIM 1000\n:l\nb = b + 1\nIF t > 0 THEN GOTO l\n", 2},
    {"event", "EN_EVT 1, h\n:l\nb = b + 1\nGOTO l\n:h\nRET_EVT\n", 1},
};
INSTANTIATE_TEST_SUITE_P(Table, BasicWaits, ::testing::ValuesIn(k_waits),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(BasicRun, ABusyLoopCountsEveryStatementUntilItWaits) {
  Rig rig;
  rig.start(":l\na = a + 1\nIF a = 100 THEN GOTO w\nGOTO l\n:w\nb = GETOBJ $6041.00\nGOTO l\n");
  rig.step(5);  // 100 statements, none of them a wait
  EXPECT_EQ(rig.interp->statements_since_wait(), 100U);
  rig.step(20);  // a = 100 at statement 298: the GETOBJ is a wait
  EXPECT_LT(rig.interp->statements_since_wait(), 400U);
  rig.interp->stop();
  rig.start(":l\nGOTO l\n");
  EXPECT_EQ(rig.interp->statements_since_wait(), 0U);
}

}  // namespace
}  // namespace mcemu::basic
