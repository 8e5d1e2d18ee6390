// The eight program slots (faulhaber.md §9.1): upload with and without load errors, the size limit,
// start/stop and the states, only one program at a time, run-time errors, power cycle, autostart.
#include "scripting/basic/programs.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

struct Fixture {
  Fixture()
      : od(test::dictionary_entries()), programs(od, store, {}, [this](const Event& e) { events.push_back(e); }) {}
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) programs.step(++now);
  }
  od::ObjectDictionary od;
  MemoryVariables store;
  std::vector<Event> events;
  Programs programs;
  std::uint64_t now = 0;
};

TEST(BasicPrograms, SlotsStartEmpty) {
  Fixture f;
  for (int s = 1; s <= Programs::k_slots; ++s) EXPECT_EQ(f.programs.status(s).state, SlotState::empty);
  EXPECT_EQ(f.programs.running(), 0);
  EXPECT_EQ(f.programs.start(1), Programs::Start::not_startable);
  EXPECT_EQ(f.programs.start(0), Programs::Start::bad_slot);
  EXPECT_EQ(f.programs.start(9), Programs::Start::bad_slot);
  EXPECT_EQ(f.programs.upload(9, "a = 1"), Programs::Upload::bad_slot);
  EXPECT_EQ(to_string(SlotState::stopped), "stopped");
}

TEST(BasicPrograms, AnUploadWithALoadErrorIsStoredInStateError) {
  Fixture f;
  ASSERT_EQ(f.programs.upload(2, "a = 1\nGOTO Nowhere\n"), Programs::Upload::ok);
  const auto st = f.programs.status(2);
  EXPECT_EQ(st.state, SlotState::error);
  EXPECT_EQ(st.line, 2U);
  EXPECT_EQ(st.message, "unknown label 'nowhere'");
  EXPECT_TRUE(st.load_error);
  EXPECT_EQ(st.bytes, 19U);
  EXPECT_EQ(f.programs.source(2), "a = 1\nGOTO Nowhere\n");
  EXPECT_EQ(f.programs.start(2), Programs::Start::not_startable);
}

TEST(BasicPrograms, TooLargeChangesNothing) {
  Fixture f;
  ASSERT_EQ(f.programs.upload(1, "a = 1\n"), Programs::Upload::ok);
  EXPECT_EQ(f.programs.upload(1, std::string(4097, '\'')), Programs::Upload::too_large);
  EXPECT_EQ(f.programs.status(1).state, SlotState::loaded);
  EXPECT_EQ(f.programs.source(1), "a = 1\n");
}

TEST(BasicPrograms, StartRunEndAndRestart) {
  Fixture f;
  ASSERT_EQ(f.programs.upload(3, "a = a + 1\n"), Programs::Upload::ok);
  EXPECT_EQ(f.programs.status(3).state, SlotState::loaded);
  ASSERT_EQ(f.programs.start(3), Programs::Start::ok);
  EXPECT_EQ(f.programs.status(3).state, SlotState::running);
  EXPECT_EQ(f.programs.running(), 3);
  EXPECT_EQ(f.programs.running_line(), 1U);
  f.step();
  EXPECT_EQ(f.programs.status(3).state, SlotState::stopped);
  EXPECT_EQ(f.programs.running(), 0);
  ASSERT_EQ(f.programs.start(3), Programs::Start::ok);
  f.step();
  EXPECT_EQ(f.od.number(0x3005, 1), 2);
  ASSERT_GE(f.events.size(), 2U);
  EXPECT_EQ(f.events[0].kind, EventKind::started);
  EXPECT_EQ(f.events[0].slot, 3);
}

TEST(BasicPrograms, OnlyOneProgramRuns) {
  Fixture f;
  f.programs.upload(1, ":L\nGOTO L\n");
  f.programs.upload(2, ":L\nGOTO L\n");
  f.programs.start(1);
  f.step();
  f.programs.start(2);
  EXPECT_EQ(f.programs.running(), 2);
  EXPECT_EQ(f.programs.status(1).state, SlotState::stopped);
  EXPECT_EQ(f.programs.status(2).state, SlotState::running);
  f.programs.stop();
  EXPECT_EQ(f.programs.status(2).state, SlotState::stopped);
  EXPECT_EQ(f.programs.running(), 0);
}

TEST(BasicPrograms, ARunTimeErrorLeavesTheSlotInErrorUntilReuploadOrPowerCycle) {
  Fixture f;
  f.programs.upload(4, "a = 1\nb = 1 / 0\n");
  f.programs.start(4);
  f.step();
  auto st = f.programs.status(4);
  EXPECT_EQ(st.state, SlotState::error);
  EXPECT_EQ(st.line, 2U);
  EXPECT_EQ(st.message, "division by zero");
  EXPECT_FALSE(st.load_error);
  EXPECT_EQ(f.programs.start(4), Programs::Start::not_startable);
  f.programs.power_cycle();
  EXPECT_EQ(f.programs.status(4).state, SlotState::loaded);
  EXPECT_EQ(f.programs.start(4), Programs::Start::ok);
}

TEST(BasicPrograms, AnOdErrorCarriesItsAbortCode) {
  Fixture f;
  f.programs.upload(1, "SETOBJ $6041.00 = 1\n");
  f.programs.start(1);
  f.step();
  EXPECT_EQ(f.programs.status(1).code, od::AbortCode::read_only);
}

TEST(BasicPrograms, UploadOrEraseOfTheRunningSlotStopsIt) {
  Fixture f;
  f.programs.upload(1, ":L\nGOTO L\n");
  f.programs.start(1);
  f.programs.upload(1, "a = 5\n");
  EXPECT_EQ(f.programs.running(), 0);
  EXPECT_EQ(f.programs.status(1).state, SlotState::loaded);
  f.programs.start(1);
  EXPECT_TRUE(f.programs.erase(1));
  EXPECT_EQ(f.programs.running(), 0);
  EXPECT_EQ(f.programs.status(1).state, SlotState::empty);
  f.step(3);  // nothing runs, nothing dangles
  EXPECT_EQ(f.od.number(0x3005, 1), 0);
}

TEST(BasicPrograms, PowerCycleStopsAndAutostartStartsAgain) {
  Fixture f;
  f.programs.upload(5, "a = a + 1\n:L\nGOTO L\n");
  f.programs.upload(6, "GOTO x\n");  // load error: stays in error
  EXPECT_FALSE(f.programs.set_autostart(9));
  ASSERT_TRUE(f.programs.set_autostart(5));
  EXPECT_EQ(f.programs.autostart(), 5);
  EXPECT_TRUE(f.programs.start_autostart());
  f.step();
  f.programs.power_cycle();
  EXPECT_EQ(f.programs.running(), 0);
  EXPECT_EQ(f.programs.status(5).state, SlotState::loaded);
  EXPECT_EQ(f.programs.status(6).state, SlotState::error);
  EXPECT_EQ(describe(f.events.back()), "stop slot 5 (power cycle)");
  EXPECT_TRUE(f.programs.start_autostart());
  EXPECT_EQ(f.programs.running(), 5);
  ASSERT_TRUE(f.programs.set_autostart(6));
  f.programs.power_cycle();
  EXPECT_FALSE(f.programs.start_autostart()) << "a program with a load error cannot start";
  ASSERT_TRUE(f.programs.set_autostart(0));
  EXPECT_FALSE(f.programs.start_autostart());
}

TEST(BasicPrograms, QuietWhileNothingRuns) {
  Fixture f;
  EXPECT_EQ(f.programs.quiet_steps(), k_never);
  f.programs.upload(1, ":L\nGOTO L\n");
  f.programs.start(1);
  EXPECT_EQ(f.programs.quiet_steps(), 0U);
  f.step(2);
  EXPECT_EQ(f.programs.quiet_steps(), k_never) << "GOTO to itself changes nothing";
  f.programs.skip(1000);
  EXPECT_EQ(f.programs.running(), 1);
}

}  // namespace
}  // namespace mcemu::basic
