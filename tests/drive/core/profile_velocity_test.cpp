// Profile velocity mode (drive-core.md §8, §15 item 12): ramps, reversal, velocity window and
// threshold bits, halt, soft-limit braking, clamping to 607Fh.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

TEST(ProfileVelocity, RampWindowAndReversalNumbers) {
  Drive d;
  d.enable(3);
  EXPECT_EQ(d.sw(), 0x1027) << "speed = 0 at mode entry";
  d.set(0x60FF, 0, 1000);
  int reached_demand = -1;
  int bit10 = -1;
  for (int k = 1; k <= 800; ++k) {
    d.step();
    if (reached_demand < 0 && d.read(0x606B) == 1000) reached_demand = k;
    if (bit10 < 0 && (d.sw() & 0x0400)) bit10 = k;
  }
  EXPECT_EQ(reached_demand, 600);
  EXPECT_NEAR(bit10, 640, 10);
  EXPECT_NEAR(static_cast<double>(d.read(0x606C)), 1000, 2);
  d.set(0x60FF, 0, -1000);
  EXPECT_FALSE(d.sw() & 0x0400) << "a run command clears bit 10";
  int zero = -1;
  int full = -1;
  for (int k = 1; k <= 1400; ++k) {
    d.step();
    if (zero < 0 && d.read(0x606B) == 0) zero = k;
    if (full < 0 && d.read(0x606B) == -1000) full = k;
  }
  EXPECT_EQ(zero, 600);
  EXPECT_EQ(full, 1200);
}

TEST(ProfileVelocity, ReversalUsesQuickStopDeceleration) {
  Drive d;
  d.set(0x6085, 0, 4000);
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(700);
  d.set(0x60FF, 0, -1000);
  EXPECT_EQ(d.step_until([&] { return d.read(0x606B) <= 0; }, 1000), 150u);
}

TEST(ProfileVelocity, SlowingDownUsesProfileDeceleration) {
  Drive d;
  d.set(0x6084, 0, 500);
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(700);
  d.set(0x60FF, 0, 0);
  EXPECT_EQ(d.step_until([&] { return d.read(0x606B) == 0; }, 2000), 1200u);
}

TEST(ProfileVelocity, SpeedZeroBitHasTimeHysteresis) {
  Drive d;
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  // |v| passes 606Fh = 100 rpm after about 60 ms; bit 12 drops 100 ms later
  const std::uint64_t moving = d.step_until([&] { return std::llabs(d.read(0x606C)) > 100; }, 500);
  const std::uint64_t dropped = d.step_until([&] { return (d.sw() & 0x1000) == 0; }, 500);
  EXPECT_NEAR(static_cast<double>(dropped), 100, 2) << "after " << moving << " ms";
  d.step(700);
  d.set(0x60FF, 0, 0);
  const std::uint64_t slow = d.step_until([&] { return std::llabs(d.read(0x606C)) <= 100; }, 1000);
  const std::uint64_t set = d.step_until([&] { return (d.sw() & 0x1000) != 0; }, 500);
  EXPECT_NEAR(static_cast<double>(set), 100, 2) << "after " << slow << " ms";
}

TEST(ProfileVelocity, HaltAndRelease) {
  Drive d;
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(700);
  d.cw(0x10F);
  EXPECT_FALSE(d.sw() & 0x0400);
  EXPECT_EQ(d.step_until([&] { return d.read(0x606B) == 0; }, 1000), 600u);
  d.step();
  EXPECT_TRUE(d.sw() & 0x0400) << "halt ramp finished";
  d.step(100);
  EXPECT_EQ(d.read(0x606B), 0);
  d.cw(0x0F);
  EXPECT_EQ(d.step_until([&] { return d.read(0x606B) == 1000; }, 1000), 600u);
}

TEST(ProfileVelocity, TargetClampedToMaxProfileVelocity) {
  Drive d;
  d.set(0x607F, 0, 1500);
  d.set(0x6083, 0, 10000);
  d.enable(3);
  d.set(0x60FF, 0, 3000);
  d.step(500);
  EXPECT_EQ(d.read(0x606B), 1500);
}

TEST(ProfileVelocity, StartsAtOnceWhenEnabledWithTargetSet) {
  Drive d;
  d.step();
  d.set(0x6060, 0, 3);
  d.set(0x60FF, 0, 200);
  d.step();
  d.cw(0x06);
  d.cw(0x07);
  d.cw(0x0F);
  d.step(200);
  EXPECT_EQ(d.read(0x606B), 200);
}

TEST(ProfileVelocity, BrakesToStopAtSoftLimitAndMayLeave) {
  Drive d;
  d.set(0x607D, 1, -100000);
  d.set(0x607D, 2, 300000);
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  std::int64_t max_p = 0;
  for (int k = 0; k < 2000; ++k) {
    d.step();
    max_p = std::max<std::int64_t>(max_p, d.read(0x60FC));
  }
  EXPECT_EQ(max_p, 300000);
  EXPECT_EQ(d.read(0x60FC), 300000);
  EXPECT_TRUE(d.sw() & 0x0800) << "pinned at the limit";
  d.set(0x60FF, 0, -200);
  d.step(300);
  EXPECT_LT(d.read(0x60FC), 300000);
  EXPECT_FALSE(d.sw() & 0x0800);
}

TEST(ProfileVelocity, RefusedOnRabbit) {
  Drive d("MCFLAT");
  EXPECT_EQ(d.write(0x6060, 0, 3), od::AbortCode::invalid_value);
  EXPECT_EQ(d.read(0x6502), 0x21);
}

TEST(ProfileVelocity, PolarityNegatesTargetAndActual) {
  Drive d;
  d.set(0x607E, 0, 0x40);
  d.enable(3);
  d.set(0x60FF, 0, 500);
  d.step(600);
  EXPECT_EQ(d.read(0x606B), 500);
  EXPECT_LT(d.read(0x6063), 0) << "the motor turns negative";
}

}  // namespace
}  // namespace mcemu::core
