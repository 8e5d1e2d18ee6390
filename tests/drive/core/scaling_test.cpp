// Scaling (drive-core.md §3): the worked examples of §3.9 to the increment, the rounding rule,
// the factor-group checks and the rpm / user-unit switch, through Scaling and through the OD.
#include "drive/scaling.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

FactorGroup group(std::uint64_t enc, std::uint64_t gear_motor, std::uint64_t feed) {
  FactorGroup fg;
  fg.encoder_inc = enc;
  fg.gear_motor = gear_motor;
  fg.feed = feed;
  return fg;
}

Scaling rotary(const FactorGroup& fg) { return Scaling(fg, model::Kind::rotary, AccelUnit{}); }

TEST(Rounding, HalfAwayFromZeroExact) {
  EXPECT_EQ(mul_div_round(1, 1, 2), 1);
  EXPECT_EQ(mul_div_round(-1, 1, 2), -1);
  EXPECT_EQ(mul_div_round(3, 1, 2), 2);
  EXPECT_EQ(mul_div_round(-3, 1, 2), -2);
  EXPECT_EQ(mul_div_round(5, 1, 3), 2);
  EXPECT_EQ(mul_div_round(-5, 1, 3), -2);
  EXPECT_EQ(mul_div_round(0, 7, 3), 0);
  EXPECT_EQ(mul_div_round(std::numeric_limits<std::int64_t>::max(), 2, 1), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(mul_div_round(std::numeric_limits<std::int64_t>::min(), 2, 1), std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(mul_div_round(std::numeric_limits<std::int64_t>::min(), 1, 1), std::numeric_limits<std::int64_t>::min());
  // the largest allowed ratio terms stay exact: (2^62 + 1)·(2^63 − 1) / (2^63 − 1)
  const std::uint64_t big = (std::uint64_t{1} << 63) - 1;
  EXPECT_EQ(mul_div_round((std::int64_t{1} << 62) + 1, big, big), (std::int64_t{1} << 62) + 1);
  EXPECT_EQ(round_half_away(2.5), 3);
  EXPECT_EQ(round_half_away(-2.5), -3);
  EXPECT_EQ(floor_mod(-1, 360), 359);
  EXPECT_EQ(wrap_i32(std::int64_t{1} << 31), std::numeric_limits<std::int32_t>::min());
}

struct PositionCase {
  std::uint64_t enc, gear, feed;
  std::int64_t inc;
  std::int64_t user;
};

class PositionExamples : public ::testing::TestWithParam<PositionCase> {};

TEST_P(PositionExamples, IncToUser) {
  const auto& c = GetParam();
  EXPECT_EQ(rotary(group(c.enc, c.gear, c.feed)).to_user(c.inc), c.user);
}

// §3.9 rows "inc → user"
INSTANTIATE_TEST_SUITE_P(Spec39, PositionExamples,
                         ::testing::Values(PositionCase{65536, 5, 360, 29375, 32},
                                           PositionCase{65536, 5, 360, 317596, 349},
                                           PositionCase{4096, 3, 360, -186806, -5473},
                                           PositionCase{65536, 5, 100, 80000, 24}));

TEST(ScalingExamples, RatioAndUserToInc) {
  const Scaling s = rotary(group(65536, 5, 360));
  EXPECT_EQ(s.numerator(), 9u);
  EXPECT_EQ(s.denominator(), 8192u);
  EXPECT_EQ(s.to_inc(1), 910);
  EXPECT_EQ(s.to_inc(90), 81920);
  const Scaling s2 = rotary(group(4096, 3, 360));
  EXPECT_EQ(s2.numerator(), 15u);
  EXPECT_EQ(s2.denominator(), 512u);
}

TEST(ScalingExamples, Velocities) {
  const Scaling deg = rotary(group(65536, 5, 360));
  EXPECT_FALSE(deg.rpm_units());
  EXPECT_EQ(deg.velocity_from_inc_s(88 * 65536.0 / 60.0), 106);  // 105.6 °/s
  const Scaling deg2 = rotary(group(4096, 3, 360));
  EXPECT_EQ(deg2.velocity_from_inc_s(363 * 4096.0 / 60.0), 726);
  const Scaling factory = rotary(FactorGroup{});
  EXPECT_TRUE(factory.rpm_units());
  EXPECT_NEAR(factory.velocity_to_inc_s(1000), 1092266.6667, 1e-3);
  EXPECT_EQ(factory.velocity_from_inc_s(1092266.6667), 1000);
  // MAN footer: gear 1, feed 360: −1 rpm shows as −6 usr/s
  EXPECT_EQ(rotary(group(65536, 1, 360)).velocity_from_inc_s(-65536.0 / 60.0), -6);
}

TEST(ScalingExamples, AccelerationAndJerk) {
  EXPECT_NEAR(rotary(FactorGroup{}).acceleration_to_inc_s2(1000), 1820444.444, 1e-3);
  const Scaling linear(FactorGroup{}, model::Kind::linear, AccelUnit{});
  EXPECT_DOUBLE_EQ(linear.acceleration_to_inc_s2(10000), 1e7);
  EXPECT_DOUBLE_EQ(linear.jerk_to_inc_s3(500000), 5e8);
  EXPECT_DOUBLE_EQ(linear.acceleration_to_inc_s2(10000) / linear.jerk_to_inc_s3(500000), 0.02);  // T_j = 20 ms
  EXPECT_FALSE(linear.rpm_units());
  EXPECT_DOUBLE_EQ(linear.velocity_to_inc_s(1000), 1000);  // µm/s at the factory group
  EXPECT_DOUBLE_EQ(linear.speed_limit_to_inc_s(2000), 2e6);
  // the older reading of the rotary unit (ODD): 1000 inc/s² per unit
  const Scaling odd(FactorGroup{}, model::Kind::rotary, AccelUnit{1000, 65536});
  EXPECT_NEAR(odd.acceleration_to_inc_s2(1), 1000, 1e-9);
}

TEST(ScalingExamples, Polarity) {
  FactorGroup fg;
  fg.polarity = 0x80;
  const Scaling pos(fg, model::Kind::rotary, AccelUnit{});
  EXPECT_EQ(pos.to_user(100), -100);
  EXPECT_EQ(pos.to_inc(-100), 100);
  EXPECT_EQ(pos.velocity_from_inc_s(65536.0 / 60), 1);
  fg.polarity = 0x40;
  const Scaling vel(fg, model::Kind::rotary, AccelUnit{});
  EXPECT_EQ(vel.to_user(100), 100);
  EXPECT_EQ(vel.velocity_from_inc_s(65536.0 / 60), -1);
  EXPECT_DOUBLE_EQ(vel.target_velocity_to_inc_s(1), -65536.0 / 60);
}

TEST(ScalingChecks, ZeroAndHugeRatios) {
  FactorGroup fg;
  EXPECT_EQ(Scaling::check(fg), od::AbortCode::none);
  fg.feed = 0;
  EXPECT_EQ(Scaling::check(fg), od::AbortCode::value_too_low);
  fg = FactorGroup{};
  fg.encoder_inc = 4294967295u;
  fg.gear_motor = 4294967295u;
  EXPECT_EQ(Scaling::check(fg), od::AbortCode::value_too_high);
  fg.gear_motor = 1;
  EXPECT_EQ(Scaling::check(fg), od::AbortCode::none);
}

TEST(ScalingThroughOd, HooksRefuseAndReDeriveAtOnce) {
  test::Drive d;
  d.step();
  EXPECT_EQ(d.write(0x6092, 1, 0), od::AbortCode::value_too_low);
  EXPECT_EQ(d.write(0x608F, 1, 4294967295), od::AbortCode::none);
  EXPECT_EQ(d.write(0x6091, 1, 4294967295), od::AbortCode::value_too_high);
  EXPECT_EQ(d.read(0x6091, 1), 1);
  d.set(0x608F, 1, 65536);
  // run at 1000 rpm, then switch the feed: 606Ch changes unit inside the write
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(800);
  EXPECT_NEAR(static_cast<double>(d.read(0x606C)), 1000, 2);
  d.set(0x6092, 1, 360);
  // 1000 rpm = 6000 °/s with feed 360 per revolution
  EXPECT_NEAR(static_cast<double>(d.read(0x606C)), 6000, 12);
  const std::int64_t inc = d.read(0x6063);
  EXPECT_EQ(d.read(0x6064), mul_div_round(inc, 360, 65536));
}

TEST(ScalingThroughOd, InternalPositionWrapsModulo2Pow32) {
  test::Drive d("MC349", {}, false);
  d.core.power_on(PowerOnState{(std::int64_t{1} << 31) + 5, 0});
  // an incremental model starts at 6063h = 0 whatever the raw position
  EXPECT_EQ(d.read(0x6063), 0);
  test::Drive ae("MC349_AE", {}, false);
  ae.core.power_on(PowerOnState{(std::int64_t{1} << 31) + 5, 0});
  EXPECT_EQ(ae.read(0x6063), std::numeric_limits<std::int32_t>::min() + 5);
}

}  // namespace
}  // namespace mcemu::core
