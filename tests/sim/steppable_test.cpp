// sim::advance and sim::Fleet (sim/steppable.hpp): quiet stretches in one skip, full steps bounded,
// hold, and a fleet that skips its quiet drives.
#include "sim/steppable.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "tests/sim/fake_target.hpp"

namespace mcemu::sim {
namespace {

using test::FakeTarget;

TEST(Advance, QuietStretchesAreOneSkipEach) {
  FakeTarget f;
  f.needed = {10, 11, 5000};
  const Advanced r = advance(f, 100000);
  EXPECT_EQ(r.steps, 100000u);
  EXPECT_EQ(r.full, 3u);
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{10, 11, 5000}));
  EXPECT_EQ(f.skips, 3u);  // 1–9, 12–4999, 5001–100000
  EXPECT_EQ(f.t, 100000u);
}

TEST(Advance, FullStepsAreBoundedQuietOnesAreNot) {
  FakeTarget f;
  f.busy = true;
  EXPECT_EQ(advance(f, 120, 50).steps, 50u);
  f.busy = false;
  f.needed = {60, 3000000};
  const Advanced r = advance(f, 3600000 - 50, 50);
  EXPECT_EQ(r.steps, 3600000u - 50);
  EXPECT_EQ(r.full, 2u);
}

TEST(Advance, StopsAfterTheFullStepThatHolds) {
  FakeTarget f;
  f.needed = {5, 7, 9};
  const Advanced r = advance(f, 100, k_forever, [&] { return f.t == 7; });
  EXPECT_EQ(r.steps, 7u);
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{5, 7}));
}

TEST(Advance, TouchMakesTheNextStepFull) {
  FakeTarget f;
  advance(f, 10);
  f.touch();
  advance(f, 10);
  EXPECT_EQ(f.full_at, (std::vector<std::uint64_t>{11}));
}

TEST(Fleet, QuietDrivesAreSkippedWhileAnotherSteps) {
  FakeTarget a;
  FakeTarget b;
  a.needed = {3};
  b.needed = {5};
  Fleet fleet;
  fleet.add(a);
  fleet.add(b);
  EXPECT_EQ(fleet.quiet_steps(), 2u);
  const Advanced r = advance(fleet, 10);
  EXPECT_EQ(r.full, 2u);
  EXPECT_EQ(a.full_at, (std::vector<std::uint64_t>{3}));
  EXPECT_EQ(b.full_at, (std::vector<std::uint64_t>{5}));
  EXPECT_EQ(a.t, 10u);
  EXPECT_EQ(b.t, 10u);
  fleet.touch();
  EXPECT_TRUE(a.dirty && b.dirty);
}

// A fleet of a drive that needs every step and one that needs only the steps in `needed`.
struct MovingAndIdle {
  FakeTarget moving;
  FakeTarget idle;
  Fleet fleet;
  explicit MovingAndIdle(std::set<std::uint64_t> needed = {}) {
    moving.busy = true;
    idle.needed = std::move(needed);
    fleet.add(moving);
    fleet.add(idle);
  }
};

// A client of one drive of 1000 (issue 26): the fleet keeps each drive's quiet answer until the
// drive steps or is touched, and touch_drive() makes only that drive's next step full.
TEST(Fleet, AsksAQuietDriveAgainOnlyAfterItStepsOrIsTouched) {
  MovingAndIdle f({40});
  auto& [moving, idle, fleet] = f;
  EXPECT_EQ(advance(fleet, 30).full, 30u);
  EXPECT_EQ(idle.asked, 1u) << "quiet through step 39: asked once";
  EXPECT_EQ(advance(fleet, 20).full, 20u);
  EXPECT_EQ(idle.full_at, (std::vector<std::uint64_t>{40}));  // the cached answer kept its deadline
  EXPECT_EQ(idle.asked, 2u) << "asked again after its step at 40, then quiet for good";

  moving.busy = false;
  fleet.touch_drive(idle);
  EXPECT_TRUE(idle.dirty);
  EXPECT_FALSE(moving.dirty);
  const Advanced r = advance(fleet, 10);
  EXPECT_EQ(r.full, 1u) << "only the touched drive steps in full";
  EXPECT_EQ(idle.full_at.back(), 51u);
  EXPECT_EQ(moving.t, 60u);
  EXPECT_EQ(idle.t, 60u);
  // touch() of the whole fleet still touches every drive
  fleet.touch();
  EXPECT_TRUE(moving.dirty && idle.dirty);
  EXPECT_EQ(advance(fleet, 1).full, 1u);
  EXPECT_EQ(moving.full_at.back(), 61u);
  EXPECT_EQ(idle.full_at.back(), 61u);
}

// One moving drive of 1000 costs one step (issue 26): a quiet drive is not visited while another
// steps; it is left behind and settled in one skip when it next steps, is settled or touched from
// outside, or the whole fleet skips.
TEST(Fleet, QuietDrivesAreLeftBehindAndSettledInOneSkip) {
  MovingAndIdle f({300});
  auto& [moving, idle, fleet] = f;
  EXPECT_EQ(advance(fleet, 100).full, 100u);
  EXPECT_EQ(idle.t, 0u) << "left behind, never visited";
  EXPECT_EQ(idle.skips, 0u);
  fleet.settle_drive(idle);
  EXPECT_EQ(idle.t, 100u);
  EXPECT_EQ(idle.skips, 1u);
  fleet.settle_drive(idle);
  EXPECT_EQ(idle.skips, 1u) << "nothing owed: no call";
  EXPECT_EQ(advance(fleet, 50).full, 50u);
  EXPECT_EQ(idle.t, 100u);
  fleet.settle();
  EXPECT_EQ(idle.t, 150u);
  EXPECT_EQ(moving.t, 150u);
  EXPECT_EQ(idle.skips, 2u);
  // its own step: the owed steps skipped first, then the step, in the step it was due
  EXPECT_EQ(advance(fleet, 200).full, 200u);
  EXPECT_EQ(idle.full_at, (std::vector<std::uint64_t>{300}));
  EXPECT_EQ(idle.skips, 3u);
  EXPECT_EQ(idle.t, 300u) << "fleet at 350";
  // touch_drive settles before it marks the drive
  EXPECT_EQ(advance(fleet, 20).full, 20u);
  fleet.touch_drive(idle);
  EXPECT_EQ(idle.t, 370u);
  EXPECT_TRUE(idle.dirty);
  // the whole fleet quiet: one skip settles what each drive owes and the stretch together
  moving.busy = false;
  EXPECT_EQ(advance(fleet, 30).full, 1u) << "the touched drive's step";
  EXPECT_EQ(idle.full_at.back(), 371u);
  EXPECT_EQ(moving.t, 400u);
  EXPECT_EQ(idle.t, 400u);
  EXPECT_EQ(idle.skips, 5u) << "300→370 by the touch, then the fleet's last skip";
}

// A caller that changed a left-behind drive without settling it first (a contract breach) cannot
// make the fleet skip over a step the change needs: the drive is asked and steps in full.
TEST(Fleet, ADriveChangedBeforeItWasSettledStepsWhatItCannotSkip) {
  MovingAndIdle f;
  auto& [moving, idle, fleet] = f;
  advance(fleet, 10);
  EXPECT_EQ(idle.t, 0u);
  idle.dirty = true;  // changed from outside, not settled
  fleet.touch_drive(idle);
  EXPECT_EQ(idle.full_at, (std::vector<std::uint64_t>{1})) << "its first owed step ran in full";
  EXPECT_EQ(idle.t, 10u);
}

// The prefetch hints of Fleet::step: a drive far enough down the list gets every level in order,
// each one while an earlier drive steps, all before its own step; the first drive gets none.
TEST(Fleet, PrefetchesTheNextDrivesLevelByLevelBeforeTheirStep) {
  using Event = std::tuple<char, int, int>;  // ('s', drive, 0) a step, ('p', drive, level) a hint
  struct Logged final : Steppable {
    std::vector<Event>* log = nullptr;
    int id = 0;
    void step() override { log->emplace_back('s', id, 0); }
    std::uint64_t quiet_steps() const override { return 0; }
    void skip(std::uint64_t) override {}
    void touch() override {}
    void prefetch(int level) const override { log->emplace_back('p', id, level); }
  };
  std::vector<Event> log;
  std::vector<Logged> drives(6);
  Fleet fleet(6);
  for (int k = 0; k < 6; ++k) {
    drives[k].log = &log;
    drives[k].id = k;
    fleet.add(drives[k]);
  }
  fleet.step();
  const auto at = [&](Event e) {
    const auto it = std::find(log.begin(), log.end(), e);
    return it == log.end() ? -1 : static_cast<int>(it - log.begin());
  };
  static_assert(Fleet::k_prefetch_levels == 3);
  for (int k = 0; k < 6; ++k) {
    int last = -1;
    for (int level = std::max(0, 3 - k); level < 3; ++level) {  // drive k steps k drives after the first
      const int p = at({'p', k, level});
      ASSERT_GE(p, 0) << "drive " << k << " level " << level;
      EXPECT_GT(p, last) << "drive " << k << " level " << level;
      EXPECT_LT(p, at({'s', k - 1, 0})) << "drive " << k << " level " << level;
      last = p;
    }
    EXPECT_GT(at({'s', k, 0}), last) << "drive " << k;
  }
  EXPECT_EQ(std::count_if(log.begin(), log.end(), [](const Event& e) { return std::get<0>(e) == 'p'; }),
            3 + 3 + 3 + 2 + 1);
  EXPECT_EQ(std::count_if(log.begin(), log.end(), [](const Event& e) { return std::get<0>(e) == 's'; }), 6);

  // a smaller fleet than asked for steps without hints
  log.clear();
  Fleet small(7);
  for (auto& d : drives) small.add(d);
  small.step();
  EXPECT_EQ(std::count_if(log.begin(), log.end(), [](const Event& e) { return std::get<0>(e) == 'p'; }), 0);
}

}  // namespace
}  // namespace mcemu::sim
