// The saturating step count of the supply monitors (drive/step_count.hpp, drive-core.md §10.11):
// +1 per step while the condition holds, 0 when it does not, skips add their length, and weeks of
// a held condition neither overflow nor fall below the 2-step debounce.
#include "drive/step_count.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

namespace mcemu::core {
namespace {

TEST(StepCount, CountsHeldStepsAndRestartsAtZero) {
  StepCount c;
  EXPECT_FALSE(c.at_least(1));
  c.step(true);
  EXPECT_EQ(c.value(), 1u);
  EXPECT_FALSE(c.at_least(2));
  c.step(true);
  EXPECT_TRUE(c.at_least(2));
  c.step(false);
  EXPECT_EQ(c.value(), 0u);
  c.skip(true, 5);
  EXPECT_EQ(c.value(), 5u);
  c.skip(false, 5);
  EXPECT_EQ(c.value(), 0u);
  c.step(true);
  c.reset();
  EXPECT_EQ(c.value(), 0u);
}

// An int of ms overflowed after 2^31 steps (about 24.8 days): the count went negative and the fault
// was no longer raised. Now it stops at k_max and stays there, by steps and by skips alike.
TEST(StepCount, SaturatesInsteadOfOverflowing) {
  const std::uint64_t days_25 = 25ULL * 24 * 3600 * 1000;
  StepCount c;
  c.skip(true, days_25);
  EXPECT_EQ(c.value(), days_25);
  c.step(true);
  EXPECT_EQ(c.value(), days_25 + 1);
  EXPECT_GT(c.value(), static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()));
  c.skip(true, std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(c.value(), StepCount::k_max);
  c.step(true);
  c.skip(true, 1000);
  EXPECT_EQ(c.value(), StepCount::k_max);
  EXPECT_TRUE(c.at_least(2));
  c.step(false);
  EXPECT_EQ(c.value(), 0u);
}

}  // namespace
}  // namespace mcemu::core
