// sim::advance and sim::Fleet (sim/steppable.hpp): quiet stretches in one skip, full steps bounded,
// hold, and a fleet that skips its quiet drives.
#include "sim/steppable.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace mcemu::sim
