// Profile position mode through the OD (drive-core.md §7, §15 items 4–9): handshake, single
// set-point, set of set-points, change immediately, change on set-point, relative references,
// soft limits, rotary operation, halt, quick stop / continue, mode 0.
#include <gtest/gtest.h>

#include <cmath>

#include "drive/helpers/helpers.hpp"
#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

void start(Drive& d, std::int64_t target, std::uint16_t arm = 0x2F, std::uint16_t fire = 0x3F) {
  d.set(0x607A, 0, target);
  d.cw(arm);
  d.cw(fire);
}

TEST(ProfilePosition, SingleMoveFactoryMc349) {
  Drive d;
  d.enable(1);
  EXPECT_EQ(d.sw(), 0x0027);
  d.set(0x6081, 0, 1000);
  start(d, 65536);
  EXPECT_EQ(d.sw(), 0x1127);
  std::int64_t max_fe = 0;
  std::int64_t max_cur = 0;
  int bit10 = -1;
  for (int k = 1; k <= 700; ++k) {
    d.step();
    max_fe = std::max<std::int64_t>(max_fe, std::llabs(d.read(0x60FC) - d.read(0x6063)));
    max_cur = std::max<std::int64_t>(max_cur, std::llabs(d.read(0x6078)));
    if (k == 99) {
      EXPECT_EQ(d.sw() & 0x1000, 0x1000);
    }
    if (k == 100) {
      EXPECT_EQ(d.sw(), 0x0127) << "bit 12 drops at the end of step 100 with bit 4 still 1";
    }
    if (k == 378) {
      EXPECT_NE(d.read(0x60FC), 65536);
    }
    if (k >= 380) {
      EXPECT_EQ(d.read(0x60FC), 65536) << k;
    }
    if (bit10 < 0 && (d.sw() & 0x0400)) {
      bit10 = k;
      EXPECT_EQ(d.read(0x6064), 65536);
      EXPECT_LT(std::llabs(d.read(0x60FC) - d.read(0x6063)), 1);
    }
  }
  EXPECT_NEAR(bit10, 480, 2);
  EXPECT_LT(max_fe, 50);
  EXPECT_LT(max_cur, 100);
  EXPECT_EQ(d.sw(), 0x0427);
  const auto reached = d.of<TargetReached>();
  ASSERT_FALSE(reached.empty());
  EXPECT_EQ(reached.back().mode, 1);
}

TEST(ProfilePosition, AcknowledgeDropsWhenBitFourReturns) {
  Drive d;
  d.enable(1);
  start(d, 10000);
  EXPECT_EQ(d.sw() & 0x1000, 0x1000);
  d.cw(0x2F);
  EXPECT_EQ(d.sw() & 0x1000, 0) << "bit 4 low and room in the buffer: bit 12 drops in the write";
}

TEST(ProfilePosition, PeakVelocityAndDurationWithinOnePercent) {
  Drive d;
  d.enable(1);
  d.set(0x6081, 0, 1000);
  d.set(0x6083, 0, 2000);
  d.set(0x6084, 0, 500);
  start(d, 20 * 65536);
  double peak = 0;
  int done = -1;
  for (int k = 1; k <= 5000 && done < 0; ++k) {
    d.step();
    peak = std::max(peak, static_cast<double>(d.read(0x606B)));
    if (d.read(0x60FC) == 20 * 65536 && d.read(0x606B) == 0) done = k;
  }
  // a = 55.6 rev/s², d = 13.9 rev/s², 1000 rpm: 0.3 s + 1.2 s ramps, cruise for the rest
  const double v = 1000.0 / 60;  // rev/s
  const double ta = v / (2000.0 / 36);
  const double td = v / (500.0 / 36);
  const double t = ta + td + (20 - v * ta / 2 - v * td / 2) / v;
  EXPECT_NEAR(peak, 1000, 10);
  EXPECT_NEAR(done / 1000.0, t, 0.01 * t);
}

TEST(ProfilePosition, SetOfSetPointsBuffersTwentyAndRejectsTheNext) {
  Drive d;
  d.enable(1);
  d.set(0x6081, 0, 2000);
  start(d, 65536, 0x0F, 0x1F);
  d.step();
  std::vector<std::int64_t> targets;
  for (int i = 1; i <= 21; ++i) {
    d.cw(0x0F);
    d.set(0x607A, 0, 65536 + i * 1000);
    d.cw(0x1F);
    if (i <= 20) {
      targets.push_back(65536 + i * 1000);
      EXPECT_EQ(d.sw() & 0x1000, 0x1000);
    }
  }
  const auto accepted = d.of<SetpointAccepted>();
  ASSERT_EQ(accepted.size(), 21u);
  for (std::size_t i = 1; i < accepted.size(); ++i) EXPECT_TRUE(accepted[i].buffered);
  ASSERT_EQ(d.of<SetpointRejected>().size(), 1u);
  EXPECT_EQ(d.of<SetpointRejected>()[0].reason, SetpointRejectReason::buffer_full);
  EXPECT_EQ(d.sw() & 0x1000, 0x1000) << "buffer full: bit 12 stays 1";
  // visit the running target and then the 20 buffered targets, in order
  std::vector<std::int64_t> visited;
  std::int64_t last = -1;
  for (int k = 0; k < 20000 && visited.size() < 21; ++k) {
    d.step();
    const std::int64_t p = d.read(0x60FC);
    if (p != last && (p == 65536 || (p > 65536 && (p - 65536) % 1000 == 0 && d.read(0x606B) == 0))) {
      if (visited.empty() || visited.back() != p) visited.push_back(p);
    }
    last = p;
    if (k == 1 && visited.empty()) {
      EXPECT_EQ(d.sw() & 0x1000, 0x1000);
    }
  }
  ASSERT_EQ(visited.size(), 21u);
  EXPECT_EQ(visited[0], 65536);
  for (int i = 1; i <= 20; ++i)
    EXPECT_EQ(visited[static_cast<std::size_t>(i)], targets[static_cast<std::size_t>(i - 1)]);
  d.step(300);
  EXPECT_EQ(d.sw() & 0x1000, 0) << "a slot freed up and bit 4 is 1 for more than 100 ms";
  EXPECT_TRUE(d.sw() & 0x0400);
}

TEST(ProfilePosition, ChangeImmediatelyReversesWithinDeceleration) {
  Drive d;
  d.enable(1);
  start(d, 10 * 65536);
  d.step(400);
  const double v_before = static_cast<double>(d.read(0x606B));
  ASSERT_GT(v_before, 500);
  d.set(0x607A, 0, 0);
  d.cw(0x2F);
  d.cw(0x3F);
  std::int64_t prev = d.read(0x606B);
  bool went_negative = false;
  for (int k = 0; k < 3000; ++k) {
    d.step();
    const std::int64_t v = d.read(0x606B);
    // 6084h = 1000 → 1666.7 rpm/s, 1.67 rpm per step (+1 for rounding)
    EXPECT_LE(std::llabs(v - prev), 3) << k;
    went_negative = went_negative || v < 0;
    prev = v;
  }
  EXPECT_TRUE(went_negative);
  EXPECT_EQ(d.read(0x60FC), 0);
}

TEST(ProfilePosition, ChangeOnSetPointPassesIntermediateTargetAtSpeed) {
  Drive d;
  d.enable(1);
  d.set(0x6081, 0, 1000);
  start(d, 20 * 65536, 0x0F, 0x1F);
  d.cw(0x0F);
  d.set(0x607A, 0, 40 * 65536);
  d.cw(0x21F);
  double v_at_pass = 0;
  std::int64_t prev = 0;
  for (int k = 0; k < 5000; ++k) {
    d.step();
    const std::int64_t p = d.read(0x60FC);
    if (prev < 20 * 65536 && p >= 20 * 65536) v_at_pass = static_cast<double>(d.read(0x606B));
    prev = p;
  }
  EXPECT_GE(v_at_pass, 900);
  EXPECT_EQ(d.read(0x60FC), 40 * 65536);
}

TEST(ProfilePosition, ChangeOnSetPointOppositeDirectionStops) {
  Drive d;
  d.enable(1);
  start(d, 5 * 65536, 0x0F, 0x1F);
  d.cw(0x0F);
  d.set(0x607A, 0, 0);
  d.cw(0x21F);
  std::int64_t max_p = 0;
  for (int k = 0; k < 5000; ++k) {
    d.step();
    max_p = std::max<std::int64_t>(max_p, d.read(0x60FC));
  }
  EXPECT_EQ(max_p, 5 * 65536) << "v_end = 0 when the next target lies behind";
  EXPECT_EQ(d.read(0x60FC), 0);
}

TEST(ProfilePosition, RelativeToLastTargetAndToInterruptedTarget) {
  Drive d;
  d.enable(1);
  start(d, 10000);
  d.step(600);
  start(d, 5000, 0x4F, 0x5F);  // 60F2h = 0: relative to the last target
  d.step(600);
  EXPECT_EQ(d.read(0x6064), 15000);
  // interrupt a move by quick stop 605Ah = 6, re-enable, then +1000 is relative to the interrupted target
  d.set(0x605A, 0, 6);
  start(d, 100000);
  d.step(100);
  d.cw(0x0B);
  d.step(500);
  ASSERT_EQ(d.sw() & 0x6F, 0x07);
  const std::int64_t stopped = d.read(0x6064);
  EXPECT_LT(stopped, 100000);
  d.cw(0x0F);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  start(d, 1000, 0x4F, 0x5F);
  EXPECT_EQ(d.core.last_setpoint_target_inc(), 101000);
  d.step(1500);
  EXPECT_EQ(d.read(0x6064), 101000);
}

TEST(ProfilePosition, RelativeReferenceResetAtEnable) {
  Drive d;
  d.enable(1);
  start(d, 10000);
  d.step(600);
  d.cw(0x06);
  d.step(10);
  // move the axis by hand (external load) while disabled, then enable: reference = actual
  d.core.set_external_load(0.05);
  d.step(50);
  d.core.set_external_load(0);
  d.step(500);
  const std::int64_t here = d.read(0x6064);
  EXPECT_GT(here, 10000);
  d.cw(0x07);
  d.cw(0x0F);
  EXPECT_EQ(d.core.last_internal_target_inc(), here);
  start(d, 1000, 0x4F, 0x5F);
  EXPECT_EQ(d.core.last_setpoint_target_inc(), here + 1000);
}

TEST(ProfilePosition, RelativeToDemandAndToActual) {
  for (int option : {1, 2}) {
    Drive d;
    d.enable(1);
    d.set(0x60F2, 0, option);
    start(d, 10 * 65536);
    d.step(300);
    const std::int64_t demand = d.read(0x60FC);
    const std::int64_t actual = d.read(0x6063);
    ASSERT_NE(demand, actual);
    start(d, 1000, 0x6F, 0x7F);
    EXPECT_EQ(d.core.last_setpoint_target_inc(), (option == 1 ? demand : actual) + 1000);
  }
}

TEST(ProfilePosition, MillionRelativeSetPointsDoNotDrift) {
  Drive d;
  d.set(0x6091, 1, 5);
  d.set(0x6092, 1, 360);
  d.enable(1);
  d.set(0x607A, 0, 1);
  for (int i = 0; i < 1000000; ++i) {
    d.od.write(0x6040, 0, od::Value{std::int64_t{0x6F}}, od::Origin::sdo);
    d.od.write(0x6040, 0, od::Value{std::int64_t{0x7F}}, od::Origin::sdo);
    if (i % 10000 == 0) d.core.drain_events();
  }
  EXPECT_EQ(d.core.last_internal_target_inc(), 910222222);
  EXPECT_EQ(d.core.last_setpoint_target_inc(), 910222222);
}

TEST(ProfilePosition, SoftLimitClampsAndSetsBit11UntilNextSetPoint) {
  Drive d;
  d.set(0x607D, 1, -50000);
  d.set(0x607D, 2, 50000);
  d.enable(1);
  start(d, 80000);
  EXPECT_EQ(d.core.last_setpoint_target_inc(), 50000);
  d.step(1);
  EXPECT_TRUE(d.sw() & 0x0800);
  d.step(1000);
  EXPECT_EQ(d.read(0x6064), 50000);
  EXPECT_TRUE(d.sw() & 0x0800);
  EXPECT_FALSE(d.of<InternalLimit>().empty());
  start(d, 0);
  d.step(1);
  EXPECT_FALSE(d.sw() & 0x0800);
}

TEST(ProfilePosition, SoftLimitsOffWhenBothZeroOrInverted) {
  for (auto [lo, hi] : {std::pair{0, 0}, std::pair{1000, -1000}}) {
    Drive d;
    d.set(0x607D, 1, lo);
    d.set(0x607D, 2, hi);
    d.enable(1);
    start(d, 80000);
    EXPECT_EQ(d.core.last_setpoint_target_inc(), 80000);
  }
}

TEST(ProfilePosition, LimitLoweredDuringMoveStopsAtNewLimit) {
  Drive d;
  d.set(0x607D, 1, -1000000);
  d.set(0x607D, 2, 1000000);
  d.enable(1);
  start(d, 900000);
  d.step(300);
  ASSERT_LT(d.read(0x60FC), 300000);
  d.set(0x607D, 2, 400000);
  EXPECT_TRUE(d.sw() & 0x0800);
  std::int64_t max_p = 0;
  for (int k = 0; k < 3000; ++k) {
    d.step();
    max_p = std::max<std::int64_t>(max_p, d.read(0x60FC));
  }
  EXPECT_EQ(max_p, 400000);
  EXPECT_EQ(d.read(0x60FC), 400000);
}

struct RotaryCase {
  int option;      // 60F2h
  int target;      // degrees
  int delta_sign;  // expected direction
};

class Rotary : public ::testing::TestWithParam<RotaryCase> {};

TEST_P(Rotary, TurntableFrom350) {
  const auto c = GetParam();
  Drive d;
  d.set(0x6091, 1, 5);
  d.set(0x6092, 1, 360);
  d.set(0x607D, 1, 0);
  d.set(0x607D, 2, 360);
  d.set(0x60F2, 0, c.option);
  d.set(0x6081, 0, 100);  // 100 °/s
  d.enable(1);
  start(d, 350);
  d.step(5000);
  ASSERT_EQ(d.read(0x6064), 350);
  const std::int64_t from = d.read(0x6063);
  start(d, c.target);
  bool wrapped = false;
  std::int64_t prev = 350;
  for (int k = 0; k < 10000; ++k) {
    d.step();
    const std::int64_t u = d.read(0x6064);
    EXPECT_GE(u, 0);
    EXPECT_LT(u, 360);
    if ((prev >= 355 && u <= 5) || (prev <= 5 && u >= 355)) wrapped = true;
    prev = u;
  }
  EXPECT_EQ(d.read(0x6064), c.target);
  const std::int64_t travel = d.read(0x6063) - from;
  EXPECT_EQ(travel > 0 ? 1 : -1, c.delta_sign);
  EXPECT_EQ(wrapped, (c.target < 350) == (c.delta_sign > 0));
}

// 0xC0 shortest: +20°; 0x80 positive only: +20°; 0x40 negative only: −340°; and back to 340°
INSTANTIATE_TEST_SUITE_P(Turntable, Rotary,
                         ::testing::Values(RotaryCase{0xC0, 10, +1}, RotaryCase{0x80, 10, +1}, RotaryCase{0x40, 10, -1},
                                           RotaryCase{0xC0, 340, -1}, RotaryCase{0x80, 340, +1}));

TEST(Rotary, HalfTurnGoesPositiveAndRelativeIsLiteral) {
  Drive d;
  d.set(0x6092, 1, 360);
  d.set(0x60F2, 0, 0xC0);  // limits off: range 0 … 360
  d.set(0x6081, 0, 100);
  d.enable(1);
  start(d, 180);
  EXPECT_GT(*d.core.last_setpoint_target_inc(), 0);
  d.step(10000);
  EXPECT_EQ(d.read(0x6064), 180);
  start(d, 400, 0x6F, 0x7F);  // relative: exactly +400°
  d.step(20000);
  EXPECT_EQ(d.read(0x6064), 220);
  EXPECT_EQ(d.core.last_internal_target_inc(), mul_div_round(580, 65536, 360));
}

TEST(ProfilePosition, HaltDeceleratesThenContinues) {
  Drive d;
  d.enable(1);
  start(d, 20 * 65536);
  d.step(400);
  d.cw(0x13F);
  EXPECT_FALSE(d.sw() & 0x0400);
  const std::uint64_t stopped = d.step_until([&] { return d.read(0x606B) == 0; }, 2000);
  EXPECT_NEAR(static_cast<double>(stopped), 600 * 400 / 600.0 + 1, 3);  // 6084h ramp from ~667 rpm
  d.step(2);
  EXPECT_TRUE(d.sw() & 0x0400) << "halt ramp finished";
  const std::int64_t held = d.read(0x60FC);
  d.step(200);
  EXPECT_EQ(d.read(0x60FC), held);
  d.cw(0x03F);
  d.step(5000);
  EXPECT_EQ(d.read(0x60FC), 20 * 65536);
  EXPECT_TRUE(d.sw() & 0x0400);
}

TEST(ProfilePosition, HaltOption2UsesQuickStopDeceleration) {
  Drive d;
  d.set(0x605D, 0, 2);
  d.set(0x6085, 0, 4000);
  d.enable(1);
  start(d, 20 * 65536);
  d.step(400);
  d.cw(0x13F);
  const std::uint64_t stopped = d.step_until([&] { return d.read(0x606B) == 0; }, 2000);
  EXPECT_NEAR(static_cast<double>(stopped), 100, 3);
}

TEST(ProfilePosition, QuickStopThenContinueMotionResumes) {
  Drive d;
  d.enable(1);
  start(d, 20 * 65536);
  d.step(300);
  helpers::DriveRef ref{d.core, d.od, od::Origin::script};
  helpers::stop_motion(ref);
  EXPECT_EQ(d.read(0x605A), 6);
  EXPECT_EQ(d.sw() & 0x016F, 0x0107);
  d.step(800);
  EXPECT_EQ(d.sw(), 0x0407);
  helpers::continue_motion(ref);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  d.step(10000);
  EXPECT_EQ(d.read(0x60FC), 20 * 65536);
}

TEST(ProfilePosition, ZeroProfileVelocityNeverReaches) {
  Drive d;
  d.enable(1);
  d.set(0x6081, 0, 0);
  start(d, 1000);
  d.step(1000);
  EXPECT_EQ(d.read(0x60FC), 0);
  EXPECT_FALSE(d.sw() & 0x0400);
  EXPECT_TRUE(d.sw() & 0x0100);
}

TEST(ProfilePosition, TargetReachedDropsOnSetPointEvenWhenAlreadyThere) {
  Drive d;
  d.enable(1);
  d.step(150);
  EXPECT_TRUE(d.sw() & 0x0400);
  start(d, 0);
  EXPECT_FALSE(d.sw() & 0x0400);
  d.step(101);
  EXPECT_TRUE(d.sw() & 0x0400);
}

TEST(ProfilePosition, BitTenRisesWindowTimeAfterEnable) {
  Drive d;
  d.enable(1);
  EXPECT_EQ(d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 500), 101u);
}

TEST(NoMode, HoldsPositionAndReportsTargetReached) {
  Drive d;
  d.enable(0);
  EXPECT_EQ(d.read(0x6061), 0);
  start(d, 100000);
  d.step(300);
  EXPECT_EQ(d.read(0x60FC), 0) << "no motion commands in mode 0";
  EXPECT_EQ(d.sw(), 0x0427);
}

TEST(ModeSwitch, FromVelocityAtRestToPositionStartsSetPointsAtOnce) {
  Drive d;
  d.enable(3);
  d.step(10);
  d.set(0x6060, 0, 1);
  d.step(101);
  EXPECT_TRUE(d.sw() & 0x0400) << "the held position counts as reached";
  start(d, 3000, 0x0F, 0x1F);  // set of set-points: starts at once only when the generator is idle
  EXPECT_FALSE(d.of<SetpointAccepted>().back().buffered);
  d.step(500);
  EXPECT_EQ(d.read(0x60FC), 3000);
  EXPECT_TRUE(d.sw() & 0x0400);
}

TEST(ModeSwitch, BumplessFromVelocityToPosition) {
  Drive d;
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(800);
  d.set(0x6060, 0, 1);
  EXPECT_EQ(d.read(0x6061), 3);
  d.step();
  EXPECT_EQ(d.read(0x6061), 1);
  EXPECT_EQ(d.of<ModeDisplayChanged>().back().mode, 1);
  std::int64_t prev = d.read(0x606B);
  for (int k = 0; k < 700; ++k) {
    d.step();
    const std::int64_t v = d.read(0x606B);
    EXPECT_LE(std::llabs(v - prev), 3);
    prev = v;
  }
  EXPECT_EQ(d.read(0x606B), 0);
}

}  // namespace
}  // namespace mcemu::core
