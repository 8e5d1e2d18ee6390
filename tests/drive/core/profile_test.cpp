// Trajectory generation (drive-core.md §7.6, §7.7, §4.5): the closed-form trapezoid against the
// analytic solution, blending, stop ramps, and the RABBIT moving-average S-curve bounds.
#include "drive/profile.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drive/generator.hpp"

namespace mcemu::core {
namespace {

struct TrapCase {
  double dist, vmax, a, d;
};

// Analytic rest-to-rest trapezoid: duration and peak speed.
std::pair<double, double> analytic(const TrapCase& c) {
  const double vp_tri = std::sqrt(2 * c.a * c.d * c.dist / (c.a + c.d));
  if (vp_tri <= c.vmax) return {vp_tri / c.a + vp_tri / c.d, vp_tri};
  const double da = c.vmax * c.vmax / (2 * c.a);
  const double dd = c.vmax * c.vmax / (2 * c.d);
  return {c.vmax / c.a + c.vmax / c.d + (c.dist - da - dd) / c.vmax, c.vmax};
}

class Trapezoid : public ::testing::TestWithParam<TrapCase> {};

TEST_P(Trapezoid, DurationPeakAndEndMatchAnalytic) {
  const auto c = GetParam();
  for (double sign : {1.0, -1.0}) {
    const Profile p = Profile::move(1000, 0, 1000 + sign * c.dist, c.vmax, c.a, c.d);
    const auto [t, vp] = analytic(c);
    EXPECT_NEAR(p.duration(), t, 1e-9 * t);
    EXPECT_NEAR(p.peak_speed(), vp, 1e-9 * vp);
    EXPECT_EQ(p.at(t + 1e-3).p, 1000 + sign * c.dist);
    // sampled like the core (1 ms steps): velocity never beyond the peak, steps monotone
    double last = 1000;
    for (double k = 1; k * 1e-3 < t + 2e-3; ++k) {
      const Kinematics s = p.at(k * 1e-3);
      EXPECT_LE(std::fabs(s.v), vp * (1 + 1e-12));
      EXPECT_GE(sign * (s.p - last), -1e-9);
      last = s.p;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Trapezoid,
                         ::testing::Values(TrapCase{65536, 1092266.67, 1820444.44, 1820444.44},    // §7.6 example
                                           TrapCase{1310720, 1092266.67, 1820444.44, 1820444.44},  // with cruise
                                           TrapCase{1310720, 1092266.67, 3640888.9, 910222.2},     // a ≠ d
                                           TrapCase{100000, 500000, 1e7, 1e7},                     // §7.7 base
                                           TrapCase{1, 1000, 1e6, 1e6}));

TEST(Trapezoid, SpecExampleEndsAtStep380) {
  const Profile p = Profile::move(0, 0, 65536, 1092266.67, 1820444.44, 1820444.44);
  EXPECT_NEAR(p.duration(), 0.37947, 1e-5);
  EXPECT_FALSE(p.finished(0.379));
  EXPECT_TRUE(p.finished(0.380));
  EXPECT_NEAR(p.peak_speed(), 345405, 1);
}

TEST(Trapezoid, ReversalDeceleratesWithDThenReturns) {
  // moving +100000 inc/s, new target behind: stop with d, then travel back
  const Profile p = Profile::move(0, 100000, -5000, 200000, 1e6, 2e6);
  EXPECT_EQ(p.at(p.duration()).p, -5000);
  const Kinematics s = p.at(0.01);
  EXPECT_NEAR(s.a, -2e6, 1e-6);  // first phase: decelerate with d
  double prev_v = 100000;
  for (double k = 1; k * 1e-3 <= p.duration(); ++k) {
    const double v = p.at(k * 1e-3).v;
    EXPECT_LE(std::fabs(v - prev_v), 2e6 * 1e-3 * (1 + 1e-9));
    prev_v = v;
  }
}

TEST(Trapezoid, FinalVelocityIsLoweredWhenUnreachable) {
  const Profile p = Profile::move(0, 0, 1000, 1e6, 1e6, 1e6, 1e6);
  EXPECT_NEAR(p.end_velocity(), std::sqrt(2 * 1e6 * 1000), 1e-6);
  const Profile q = Profile::move(0, 0, 1e6, 1e5, 1e6, 1e6, 5e4);
  EXPECT_DOUBLE_EQ(q.end_velocity(), 5e4);
  EXPECT_EQ(q.at(q.duration()).p, 1e6);
}

TEST(Trapezoid, ZeroVelocityNeverFinishes) {
  const Profile p = Profile::move(0, 1000, 5000, 0, 1e6, 1e6);
  EXPECT_TRUE(p.endless());
  EXPECT_FALSE(p.finished(100));
  EXPECT_DOUBLE_EQ(p.at(100).v, 0);
}

TEST(StopRamp, LinearToStandstill) {
  // 1000 rpm and 6085h = 1000 as the core converts them
  const double v = 1000 * 65536.0 / 60.0;
  const double d = 1000 * 65536.0 / 36.0;
  const Profile p = Profile::stop(0, v, d);
  EXPECT_NEAR(p.duration(), 0.6, 1e-12);
  EXPECT_TRUE(p.finished(0.6));
  EXPECT_FALSE(p.finished(0.599));
  EXPECT_NEAR(p.at(0.6).p, v * 0.3, 1e-6);
}

TEST(Generator, FirstEvaluationIsOneStepAfterPlanning) {
  Generator g;
  g.reset(0);
  g.start_move(65536, 1092266.67, 1820444.44, 1820444.44);
  EXPECT_EQ(g.out().p, 0);
  g.tick();
  EXPECT_NEAR(g.out().p, 0.5 * 1820444.44 * 1e-6, 1e-9);
  for (int k = 2; k <= 380; ++k) g.tick();
  EXPECT_TRUE(g.finished());
  EXPECT_EQ(g.out().p, 65536);
}

TEST(Generator, VelocityRampReachesTargetExactly) {
  const double v = 1000 * 65536.0 / 60.0;
  const double a = 1000 * 65536.0 / 36.0;
  Generator g;
  g.reset(0);
  g.start_velocity(VelocityCommand{v, a, a, a});
  int steps = 0;
  while (g.out().v != v && steps < 1000) {
    g.tick();
    ++steps;
  }
  EXPECT_EQ(steps, 600);
  // reversal: down with `reverse`, then up with `accel`
  g.set_velocity_command(VelocityCommand{-v, a, a, 2 * a});
  steps = 0;
  while (g.out().v != 0 && steps < 1000) {
    g.tick();
    ++steps;
  }
  EXPECT_EQ(steps, 300);
}

// §7.7 test: 6083h = 10000 (10 m/s²), 60A4h = 500000 (500 m/s³), 6081h = 500000 µm/s, 100 000 µm.
TEST(SCurve, JerkAndAccelerationBoundsAndEndPoint) {
  const double a = 1e7;  // inc/s²
  const double j = 5e8;  // inc/s³
  Generator g(true);
  g.reset(0);
  g.start_move(100000, 500000, a, a, 0, j);
  EXPECT_EQ(g.filter_length(), 20);
  std::vector<double> p{0, 0, 0};
  const double trap_ms = std::ceil(Profile::move(0, 0, 100000, 500000, a, a).duration() * 1000 - 1e-6);
  int k = 0;
  while (!g.finished() && k < 2000) {
    g.tick();
    p.push_back(g.out().p);
    ++k;
  }
  EXPECT_EQ(k, static_cast<int>(trap_ms) + 20 - 1);
  EXPECT_EQ(p.back(), 100000);
  double max_acc = 0;
  double max_jerk = 0;
  for (std::size_t i = 3; i < p.size(); ++i) {
    const double d2 = (p[i] - 2 * p[i - 1] + p[i - 2]) / 1e-6;
    const double d3 = (p[i] - 3 * p[i - 1] + 3 * p[i - 2] - p[i - 3]) / 1e-9;
    max_acc = std::max(max_acc, std::fabs(d2));
    max_jerk = std::max(max_jerk, std::fabs(d3));
  }
  EXPECT_LE(max_acc, a * (1 + 1e-9));
  EXPECT_LE(max_jerk, j * (1 + 1e-9));
  EXPECT_GT(max_jerk, 0.9 * j) << "the filter really limits the jerk at its bound";
  EXPECT_GT(max_acc, 0.99 * a);
}

TEST(SCurve, ShortMovesLimitFilterToAccelerationTime) {
  Generator g(true);
  g.reset(0);
  // vp = sqrt(a·D) = 1e5 → acceleration time 10 ms < a/j = 20 ms
  g.start_move(1000, 500000, 1e7, 1e7, 0, 5e8);
  EXPECT_EQ(g.filter_length(), 10);
  int k = 0;
  while (!g.finished() && k < 1000) {
    g.tick();
    ++k;
  }
  EXPECT_EQ(g.out().p, 1000);
}

TEST(SCurve, StopRampBypassesFilterAndLeavesItAtRest) {
  Generator g(true);
  g.reset(0);
  g.start_move(100000, 500000, 1e7, 1e7, 0, 5e8);
  for (int i = 0; i < 60; ++i) g.tick();
  const double v = g.out().v;
  EXPECT_GT(v, 0);
  g.start_stop(2e7);
  int k = 0;
  while (!g.finished() && k < 1000) {
    g.tick();
    ++k;
  }
  EXPECT_NEAR(k, std::ceil(v / 2e7 * 1000), 1);
  const double rest = g.out().p;
  g.tick();
  EXPECT_EQ(g.out().p, rest);
  EXPECT_EQ(g.out().v, 0);
  EXPECT_FALSE(g.active());
}

}  // namespace
}  // namespace mcemu::core
