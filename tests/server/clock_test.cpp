// The clock (server/clock_mode, server/clock_logic; drive-core.md §2.2, README "Time", web.md
// §8.10): --clock parsing, and the driver's decisions under a fake wall clock — catch-up bounded to
// 50 full steps per wake-up, quiet stretches in one skip, sleeping until the next needed step,
// scaled time, the manual-clock advance queue and the script hold.
#include <gtest/gtest.h>

#include <regex>

#include "server/drive_unit.hpp"
#include "server/settings.hpp"
#include "sim/clock_logic.hpp"
#include "tests/sim/fake_target.hpp"

namespace mcemu::server {
namespace {

using namespace std::chrono_literals;
using Kind = sim::ClockLogic::Next::Kind;
using sim::test::FakeTarget;
using Wall = sim::ClockLogic::Wall;

constexpr Wall ms(double v) { return Wall(static_cast<std::int64_t>(v * 1e6)); }

TEST(ClockMode, Parse) {
  EXPECT_EQ(sim::parse_clock_mode("real").kind, sim::ClockMode::Kind::real);
  EXPECT_EQ(sim::parse_clock_mode("real").scale, 1.0);
  EXPECT_EQ(sim::parse_clock_mode("manual").kind, sim::ClockMode::Kind::manual);
  EXPECT_EQ(sim::parse_clock_mode("manual").scale, 0.0);
  for (const auto& [text, x] : std::vector<std::pair<const char*, double>>{
           {"scaled:0.1", 0.1}, {"scaled:1000", 1000}, {"scaled:2.5", 2.5}, {"scaled:1", 1}, {"scaled:.5", 0.5}}) {
    const sim::ClockMode m = sim::parse_clock_mode(text);
    EXPECT_EQ(m.kind, sim::ClockMode::Kind::scaled) << text;
    EXPECT_DOUBLE_EQ(m.scale, x) << text;
    EXPECT_STREQ(m.name(), "scaled");
  }
  for (const char* bad :
       {"", "Real", "fast", "scaled", "scaled:", "scaled:0.09", "scaled:1000.1", "scaled:0", "scaled:-1", "scaled:1e2",
        "scaled:inf", "scaled:nan", "scaled:1.2.3", "scaled:.", "scaled:0x10", "scaled: 2", "manual:1"}) {
    EXPECT_THROW(sim::parse_clock_mode(bad), std::invalid_argument) << bad;
  }
}

TEST(ClockMode, CommandLineAndConfig) {
  EXPECT_EQ(parse_command_line({}).clock.kind, sim::ClockMode::Kind::real);
  EXPECT_EQ(parse_command_line({"--clock", "manual"}).clock.kind, sim::ClockMode::Kind::manual);
  EXPECT_DOUBLE_EQ(parse_command_line({"--clock=scaled:20"}).clock.scale, 20);
  EXPECT_THROW(parse_command_line({"--clock", "scaled:5000"}), UsageError);
  EXPECT_THROW(parse_command_line({"--clock"}), UsageError);
  Settings s;
  apply_config(s, nlohmann::json{{"clock", "scaled:4"}}, {});
  EXPECT_DOUBLE_EQ(s.clock.scale, 4);
  Settings t = parse_command_line({"--clock", "manual"});
  apply_config(t, nlohmann::json{{"clock", "scaled:4"}}, {"clock"});
  EXPECT_EQ(t.clock.kind, sim::ClockMode::Kind::manual);  // the command line wins
  EXPECT_NE(help_text().find("--clock MODE"), std::string::npos);
}

TEST(ClockLogic, RealTimeRunsOneStepPerElapsedMillisecond) {
  FakeTarget f;
  f.busy = true;
  sim::ClockLogic c(f, {});
  c.start(ms(1000));
  auto next = c.on_wake(ms(1005.5));
  EXPECT_EQ(f.t, 5u);
  EXPECT_EQ(f.fulls, 5u);
  ASSERT_EQ(next.kind, Kind::sleep_until);
  EXPECT_EQ(next.at, ms(1006));
  next = c.on_wake(ms(1006));
  EXPECT_EQ(f.t, 6u);
  EXPECT_EQ(next.at, ms(1007));
}

// The server starts real and scaled clocks with the first step due at once: a client served right
// after "ready" finds the drive past its power-on step (Not ready to switch on → Switch on disabled).
TEST(ClockLogic, FirstStepDueAtStartWhenAsked) {
  for (const double scale : {1.0, 2.0, 0.5}) {
    FakeTarget f;
    f.busy = true;
    sim::ClockMode mode;
    mode.scale = scale;
    if (scale != 1.0) mode.kind = sim::ClockMode::Kind::scaled;
    sim::ClockLogic c(f, mode);
    c.start(ms(1000), true);
    (void)c.sync(ms(1000));
    EXPECT_EQ(f.t, 1u) << "scale " << scale;
    const auto next = c.on_wake(ms(1000 + 1 / scale));  // one step's wall time later: the second
    EXPECT_EQ(f.t, 2u) << "scale " << scale;
    EXPECT_EQ(next.at, ms(1000 + 2 / scale)) << "scale " << scale;
  }
  FakeTarget manual;
  sim::ClockMode m;
  m.kind = sim::ClockMode::Kind::manual;
  sim::ClockLogic c(manual, m);
  c.start(ms(1000), true);
  (void)c.sync(ms(5000));
  EXPECT_EQ(manual.t, 0u) << "the manual clock waits for an advance";
}

// A client's input for one drive of a fleet makes that drive's next step full, not every drive's.
TEST(ClockLogic, SyncForOneDriveOfAFleetTouchesThatDriveOnly) {
  FakeTarget a;
  FakeTarget b;
  sim::Fleet fleet;
  fleet.add(a);
  fleet.add(b);
  sim::ClockLogic c(fleet, {});
  c.start(ms(1000));
  auto next = c.sync(ms(1003.2), &b);
  EXPECT_EQ(a.t, 3u);  // a quiet fleet skips every drive
  EXPECT_EQ(b.t, 3u);
  EXPECT_FALSE(a.dirty);
  EXPECT_TRUE(b.dirty);
  ASSERT_EQ(next.kind, Kind::sleep_until);
  EXPECT_EQ(next.at, ms(1004));
  next = c.on_wake(ms(1004));
  EXPECT_TRUE(a.full_at.empty());
  EXPECT_EQ(b.full_at, (std::vector<std::uint64_t>{4}));
  EXPECT_EQ(next.kind, Kind::wait) << "both quiet for good";
  (void)c.touch(&a);
  EXPECT_TRUE(a.dirty);
  EXPECT_FALSE(b.dirty);
  (void)c.sync(ms(1010));
  EXPECT_TRUE(a.dirty && b.dirty) << "no drive named: every drive";
}

TEST(ClockLogic, BehindItRunsAtMost50FullStepsPerWakeUp) {
  FakeTarget f;
  f.busy = true;
  sim::ClockLogic c(f, {});
  c.start(ms(0));
  std::vector<std::uint64_t> lags;
  auto next = c.on_wake(ms(200));
  while (next.kind == Kind::now) {
    lags.push_back(next.lag);
    next = c.on_wake(ms(200));
  }
  EXPECT_EQ(lags, (std::vector<std::uint64_t>{150, 100, 50}));
  EXPECT_EQ(f.t, 200u);
  EXPECT_EQ(next.kind, Kind::sleep_until);
  EXPECT_EQ(next.at, ms(201));
}

// Expensive steps (an MC BASIC program at a high budget): a wake-up stops after the full step that
// used up k_max_wall_per_wake, well before 50 steps, and asks to come back at once; every step still
// runs, in order, so only the slicing changes.
TEST(ClockLogic, BehindAWakeUpEndsOnceItHasTakenItsWallTimeBudget) {
  FakeTarget f;
  f.busy = true;
  Wall wall = ms(200);  // each step costs 0.7 ms of wall time: the third one crosses 2 ms
  struct Costly final : sim::Steppable {
    FakeTarget& f;
    Wall& wall;
    Costly(FakeTarget& t, Wall& w) : f(t), wall(w) {}
    void step() override {
      f.step();
      wall += ms(0.7);
    }
    std::uint64_t quiet_steps() const override { return f.quiet_steps(); }
    void skip(std::uint64_t n) override { f.skip(n); }
    void touch() override { f.touch(); }
  } target(f, wall);
  sim::ClockLogic c(target, {}, [&] { return wall; });
  c.start(ms(0));
  auto next = c.on_wake(wall);
  EXPECT_EQ(f.t, 3u);
  ASSERT_EQ(next.kind, Kind::now);
  EXPECT_EQ(next.lag, 197u);  // due(200 ms) = 200; the clock's own `now` was the wake-up's
  // a client's input while behind: served at once, at the drive time reached; no batch of its own
  next = c.sync(wall);
  EXPECT_EQ(f.t, 3u);
  EXPECT_EQ(next.kind, Kind::now);
  c.on_wake(wall);
  EXPECT_EQ(f.t, 6u);
  // manual: the same bound slices an advance; the request still completes with every step run
  FakeTarget g;
  g.busy = true;
  Costly manual_target(g, wall);
  sim::ClockLogic m(manual_target, sim::parse_clock_mode("manual"), [&] { return wall; });
  m.start(wall);
  bool done = false;
  ASSERT_TRUE(m.request(10, [&] { done = true; }));
  std::vector<std::uint64_t> after;
  while (m.plan().kind == Kind::now) {
    m.on_wake(wall);
    after.push_back(g.t);
  }
  EXPECT_EQ(after, (std::vector<std::uint64_t>{3, 6, 9, 10}));
  EXPECT_TRUE(done);
  EXPECT_EQ(g.full_at, (std::vector<std::uint64_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
}

// A single step longer than the budget still runs: one full step per wake-up at least.
TEST(ClockLogic, AStepLongerThanTheBudgetStillAdvancesOnePerWakeUp) {
  FakeTarget f;
  f.busy = true;
  Wall wall = ms(5);
  sim::ClockLogic c(f, {}, [&] {
    wall += ms(10);
    return wall;
  });
  c.start(ms(0));
  std::vector<std::uint64_t> after;
  auto next = c.on_wake(ms(5));
  after.push_back(f.t);
  while (next.kind == Kind::now) {
    next = c.on_wake(ms(5));
    after.push_back(f.t);
  }
  EXPECT_EQ(after, (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

TEST(ClockLogic, SleepsUntilTheNextNeededStepAndSkipsTheRestInOneCall) {
  FakeTarget f;
  f.needed = {1000, 60000};
  sim::ClockLogic c(f, {});
  c.start(ms(0));
  auto next = c.on_wake(ms(0.3));
  ASSERT_EQ(next.kind, Kind::sleep_until);
  EXPECT_EQ(next.at, ms(1000));  // step 1000 is due at 1 s; nothing before it needs a wake-up
  next = c.on_wake(ms(1000));
  EXPECT_EQ(f.t, 1000u);
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{1000}));
  EXPECT_EQ(f.skips, 1u);
  EXPECT_EQ(next.at, ms(60000));
  next = c.on_wake(ms(60000));
  EXPECT_EQ(next.kind, Kind::wait);  // nothing ever again: sleep until woken
  // woken late (a loaded machine): the needed step still runs, in drive-time order
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{1000, 60000}));
  EXPECT_EQ(c.full_steps(), 2u);
  EXPECT_EQ(c.ticks(), 60000u);
}

TEST(ClockLogic, SyncCatchesUpAndMakesTheNextStepFull) {
  FakeTarget f;
  sim::ClockLogic c(f, {});
  c.start(ms(0));
  EXPECT_EQ(c.on_wake(ms(0)).kind, Kind::wait);
  const auto next = c.sync(ms(3500.2));
  EXPECT_EQ(f.t, 3500u);
  EXPECT_EQ(f.fulls, 0u);
  EXPECT_TRUE(f.dirty);
  ASSERT_EQ(next.kind, Kind::sleep_until);
  EXPECT_EQ(next.at, ms(3501));
  c.on_wake(ms(3501));
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{3501}));
  EXPECT_EQ(c.plan().kind, Kind::wait);
  EXPECT_EQ(c.touch().kind, Kind::sleep_until);  // wake(): marks the next step, no time passes
  EXPECT_EQ(f.t, 3501u);
}

TEST(ClockLogic, ScaledTime) {
  FakeTarget f;
  f.busy = true;
  sim::ClockLogic fast(f, sim::parse_clock_mode("scaled:2.5"));
  fast.start(ms(0));
  auto next = fast.on_wake(ms(10));
  EXPECT_EQ(f.t, 25u);
  EXPECT_EQ(next.at, ms(10.4));
  FakeTarget g;
  g.busy = true;
  sim::ClockLogic slow(g, sim::parse_clock_mode("scaled:0.1"));
  slow.start(ms(0));
  next = slow.on_wake(ms(19.9));
  EXPECT_EQ(g.t, 1u);
  EXPECT_EQ(next.at, ms(20));
}

TEST(ClockLogic, DueAtIsTheFirstInstantAStepIsDue) {
  for (const char* mode : {"real", "scaled:0.1", "scaled:0.3", "scaled:2.5", "scaled:7", "scaled:1000"}) {
    FakeTarget f;
    sim::ClockLogic c(f, sim::parse_clock_mode(mode));
    c.start(ms(123.456789));
    for (std::uint64_t k : {1ULL, 2ULL, 3ULL, 10ULL, 999ULL, 123457ULL, 86400000ULL, 10000000000ULL}) {
      const Wall w = c.due_at(k);
      EXPECT_GE(c.due(w), k) << mode << " " << k;
      EXPECT_LT(c.due(w - Wall(1)), k) << mode << " " << k;
    }
  }
}

// due_at() remembers its last answer; a new start (new epoch) must not get the old one.
TEST(ClockLogic, DueAtAfterARestartFollowsTheNewEpoch) {
  FakeTarget f;
  sim::ClockLogic c(f, sim::parse_clock_mode("real"));
  c.start(ms(0));
  EXPECT_EQ(c.due_at(5), ms(5));
  EXPECT_EQ(c.due_at(5), ms(5));
  c.start(ms(1000));
  EXPECT_EQ(c.due_at(5), ms(1005));
  EXPECT_EQ(c.due_at(6), ms(1006));
}

// The trace's wall stamp: UTC, milliseconds, the same layout every call (formatted in two parts).
TEST(WallStamp, IsoUtcWithMilliseconds) {
  const std::regex layout(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}Z)");
  std::string last;
  for (int i = 0; i < 2000; ++i) {  // crosses at least one change of the millisecond
    const std::string s = utc_iso8601_ms();
    ASSERT_TRUE(std::regex_match(s, layout)) << s;
    EXPECT_GE(s, last);
    last = s;
  }
}

TEST(ClockLogic, ScaledIdleHourIsOneSkip) {
  FakeTarget f;
  sim::ClockLogic c(f, sim::parse_clock_mode("scaled:1000"));
  c.start(ms(0));
  c.on_wake(ms(3600000));
  EXPECT_EQ(f.t, 3600000000ULL);
  EXPECT_LE(f.skips, 1u);
}

TEST(ClockLogic, ManualRunsOnlyRequestsInSlicesOf50) {
  FakeTarget f;
  f.busy = true;
  sim::ClockLogic c(f, sim::parse_clock_mode("manual"));
  c.start(ms(0));
  EXPECT_EQ(c.on_wake(ms(50000)).kind, Kind::wait);
  EXPECT_EQ(f.t, 0u);  // drive time stands still
  int done1 = 0;
  int done2 = 0;
  ASSERT_TRUE(c.request(120, [&] {
    ++done1;
    EXPECT_EQ(f.t, 120u);
  }));
  ASSERT_TRUE(c.request(30, [&] {
    ++done2;
    EXPECT_EQ(f.t, 150u);
  }));
  std::vector<std::uint64_t> after;
  auto next = c.plan();
  while (next.kind == Kind::now) {
    next = c.on_wake(ms(0));
    after.push_back(f.t);
  }
  EXPECT_EQ(after, (std::vector<std::uint64_t>{50, 100, 120, 150}));
  EXPECT_EQ(done1, 1);
  EXPECT_EQ(done2, 1);
  EXPECT_EQ(next.kind, Kind::wait);
}

// A fleet leaves its quiet drives behind while another steps (sim::Fleet): the manual clock settles
// them after every slice (a script polling its drive time, the advance's answer read them without
// a sync), the real clock only where asked — settle() and sync() of that drive.
TEST(ClockLogic, NoDriveIsLeftBehindBetweenManualSlicesOrWhenSettled) {
  FakeTarget moving;
  FakeTarget idle;
  moving.busy = true;
  sim::Fleet fleet;
  fleet.add(moving);
  fleet.add(idle);
  sim::ClockLogic manual(fleet, sim::parse_clock_mode("manual"));
  manual.start(ms(0));
  std::vector<std::uint64_t> idle_after;
  ASSERT_TRUE(manual.request(120, [&] { EXPECT_EQ(idle.t, 120u) << "the answer reads the drive"; }));
  for (auto next = manual.plan(); next.kind == Kind::now;) {
    next = manual.on_wake(ms(0));
    idle_after.push_back(idle.t);
  }
  EXPECT_EQ(idle_after, (std::vector<std::uint64_t>{50, 100, 120}));
  EXPECT_EQ(idle.skips, 3u) << "one skip per slice, not one per step";

  FakeTarget moving2;
  FakeTarget idle2;
  moving2.busy = true;
  sim::Fleet fleet2;
  fleet2.add(moving2);
  fleet2.add(idle2);
  sim::ClockLogic real(fleet2, {});
  real.start(ms(0));
  (void)real.on_wake(ms(40));
  EXPECT_EQ(moving2.t, 40u);
  EXPECT_EQ(idle2.t, 0u);
  real.settle(&idle2);
  EXPECT_EQ(idle2.t, 40u);
  EXPECT_FALSE(idle2.dirty) << "settling marks nothing";
  (void)real.on_wake(ms(45));
  (void)real.sync(ms(45), &idle2);
  EXPECT_EQ(idle2.t, 45u);
  EXPECT_TRUE(idle2.dirty);
}

TEST(ClockLogic, ManualRefusals) {
  FakeTarget f;
  sim::ClockLogic manual(f, sim::parse_clock_mode("manual"));
  EXPECT_FALSE(manual.request(0, {}));
  EXPECT_FALSE(manual.request(sim::k_max_advance_ms + 1, {}));
  EXPECT_TRUE(manual.request(sim::k_max_advance_ms, {}));
  sim::ClockLogic real(f, {});
  EXPECT_FALSE(real.request(10, {}));
  sim::ClockLogic scaled(f, sim::parse_clock_mode("scaled:2"));
  EXPECT_FALSE(scaled.request(10, {}));
}

TEST(ClockLogic, ManualHourOfIdleIsOneSlice) {
  FakeTarget f;
  f.needed = {7, 1800000};
  sim::ClockLogic c(f, sim::parse_clock_mode("manual"));
  c.start(ms(0));
  bool done = false;
  ASSERT_TRUE(c.request(3600000, [&] { done = true; }));
  EXPECT_EQ(c.on_wake(ms(0)).kind, Kind::wait);
  EXPECT_TRUE(done);
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{7, 1800000}));
}

TEST(ClockLogic, ManualHoldPausesAfterTheStepThatWokeTheScript) {
  FakeTarget f;
  f.busy = true;
  sim::ClockLogic c(f, sim::parse_clock_mode("manual"));
  c.start(ms(0));
  bool script_running = false;
  bool woken = false;
  c.set_hold([&] {
    if (f.t == 30 && !woken) woken = script_running = true;  // step 30 wakes the script
    return script_running;
  });
  bool done = false;
  ASSERT_TRUE(c.request(40, [&] { done = true; }));
  EXPECT_EQ(c.on_wake(ms(0)).kind, Kind::wait);
  EXPECT_EQ(f.t, 30u);
  EXPECT_EQ(c.on_wake(ms(0)).kind, Kind::wait);  // still held: nothing runs
  EXPECT_EQ(f.t, 30u);
  script_running = false;  // the script sleeps again; the driver's resume() re-plans
  EXPECT_EQ(c.plan().kind, Kind::now);
  c.on_wake(ms(0));
  EXPECT_EQ(f.t, 40u);
  EXPECT_TRUE(done);
}

}  // namespace
}  // namespace mcemu::server
