// Every model preset with the core (models.md §7, drive-core.md §15 item 11): a factory PP move
// reaches bit 10 within 1000 ms, 6502h, PV refused on RABBIT; RABBIT specifics of §7.7.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

class EveryPreset : public ::testing::TestWithParam<std::string_view> {};

TEST_P(EveryPreset, FactoryMoveReachesTargetWithinOneSecond) {
  Drive d{std::string(GetParam())};
  const bool rabbit = d.preset.is_rabbit();
  EXPECT_EQ(d.read(0x6502), rabbit ? 0x21 : 0x25);
  d.enable(1);
  d.step(200);
  const std::int64_t distance = d.preset.kind == model::Kind::linear ? 20000 : 65536;
  const std::int64_t from = d.read(0x6064);
  d.set(0x607A, 0, distance);
  d.cw(0x6F);
  d.cw(0x7F);  // relative: linear axes start mid-stroke
  EXPECT_FALSE(d.sw() & 0x0400);
  const std::uint64_t ms = d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 1000);
  EXPECT_LE(ms, 1000u) << GetParam();
  EXPECT_EQ(d.read(0x60FC) - (from), distance);
  EXPECT_LE(std::llabs(d.read(0x6064) - from - distance), 5);
  if (rabbit) {
    EXPECT_EQ(d.write(0x6060, 0, 3), od::AbortCode::invalid_value);
  } else {
    EXPECT_EQ(d.write(0x6060, 0, 3), od::AbortCode::none);
  }
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(d.read(0x1002), 0);
}

INSTANTIATE_TEST_SUITE_P(Models, EveryPreset, ::testing::ValuesIn(model::preset_names()),
                         [](const auto& p) { return std::string(p.param); });

TEST(Rabbit, AccelerationWriteCopiesToDecelerationOnly) {
  Drive d("MCFLAT");
  d.set(0x6083, 0, 5000);
  EXPECT_EQ(d.read(0x6084), 5000);
  d.set(0x6084, 0, 100);
  EXPECT_EQ(d.read(0x6083), 5000);
  Drive mc("MC349");
  mc.set(0x6083, 0, 5000);
  EXPECT_EQ(mc.read(0x6084), 1000);
}

std::uint64_t rabbit_move_ms(std::int64_t dec) {
  Drive d("MCFLAT");
  d.set(0x6083, 0, 10000);
  d.set(0x6084, 0, dec);
  d.set(0x6081, 0, 500000);
  d.set(0x60A4, 0, 500000);
  d.enable(1);
  d.set(0x607A, 0, 50000);
  d.cw(0x6F);
  d.cw(0x7F);
  const std::int64_t target = d.read(0x60FC) + 50000;
  return d.step_until([&] { return d.read(0x60FC) == target && d.read(0x606B) == 0; }, 5000);
}

TEST(Rabbit, DecelerationDoesNotChangeProfileMoves) {
  // trapezoid 50000 µm at 10 m/s², 0.5 m/s: 50 + 50 ms ramps, 50 ms cruise; + n_j − 1 = 19 ms
  const std::uint64_t a = rabbit_move_ms(10000);
  const std::uint64_t b = rabbit_move_ms(100);
  EXPECT_EQ(a, b);
  EXPECT_NEAR(static_cast<double>(a), 150 + 19, 2);
}

TEST(Rabbit, HaltUsesTheCurrentDecelerationValue) {
  Drive d("MCFLAT");
  d.set(0x6081, 0, 500000);
  d.set(0x6083, 0, 10000);
  d.set(0x6084, 0, 2000);  // 2 m/s²
  d.enable(1);
  d.set(0x607A, 0, 90000);
  d.cw(0x6F);
  d.cw(0x7F);
  d.step(80);
  d.cw(0x17F);
  const double v = static_cast<double>(d.read(0x606B));  // µm/s
  const std::uint64_t ms = d.step_until([&] { return d.read(0x606B) == 0; }, 2000);
  EXPECT_NEAR(static_cast<double>(ms), v / 2e6 * 1000, 3);
}

TEST(Rabbit, ControllerMassFollowsWeightObjects) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::inertia_load, 2.0);  // a payload the controller does not know about
  const auto run = [&](std::int64_t payload_g) {
    Drive d("MCFLAT", cfg);
    d.set(0x3301, 4, payload_g);
    d.enable(1);
    d.set(0x607A, 0, 20000);
    d.cw(0x6F);
    d.cw(0x7F);
    std::int64_t fe = 0;
    for (int k = 0; k < 600; ++k) {
      d.step();
      fe = std::max<std::int64_t>(fe, std::llabs(d.read(0x60F4)));
    }
    return fe;
  };
  EXPECT_LT(run(2000), run(0)) << "3301h.04 tells the controller about the payload";
}

TEST(Plant, ThreeTimesControllerInertiaStaysDamped) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::inertia_load, 4e-5);
  Drive d("MC349", cfg);
  d.enable(1);
  d.set(0x607A, 0, 65536);
  d.cw(0x2F);
  d.cw(0x3F);
  std::int64_t overshoot = 0;
  for (int k = 0; k < 1000; ++k) {
    d.step();
    overshoot = std::max<std::int64_t>(overshoot, d.read(0x6063) - 65536);
  }
  EXPECT_LT(overshoot, 50);
  EXPECT_TRUE(d.sw() & 0x0400);
}

TEST(Plant, ConstantSpeedFollowingErrorIsSmall) {
  Drive d;
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(1000);
  EXPECT_LT(std::llabs(d.read(0x60FC) - d.read(0x6063)), 5);
  EXPECT_NEAR(static_cast<double>(d.read(0x606C)), 1000, 1);
}

TEST(Plant, LinearStrokeIsAMechanicalStop) {
  Drive d("MCSHORT");
  d.set(0x3401, 0x1A, 15);
  d.enable(1);
  d.set(0x607A, 0, 100000);  // 100 mm on a 46 mm stroke (absolute: 6063h = raw)
  d.cw(0x2F);
  d.cw(0x3F);
  d.step(3000);
  EXPECT_EQ(d.core.raw_position_inc(), 46000);
}

}  // namespace
}  // namespace mcemu::core

namespace mcemu::core {
namespace {

TEST(Plant, NoiseIsSeededBoundedAndOffByDefault) {
  const auto trace = [](bool enabled, std::uint64_t seed) {
    PlantConfig cfg;
    cfg.noise.enabled = enabled;
    cfg.noise.seed = seed;
    test::Drive d("MC349", cfg);
    d.enable(1);
    std::vector<std::int64_t> v;
    for (int k = 0; k < 200; ++k) {
      d.step();
      v.push_back(d.read(0x6063));
      EXPECT_LE(std::llabs(v.back()), 2);
      EXPECT_LE(std::llabs(d.read(0x606C)), 8);  // 4 inc per ms at most = 3.7 rpm
    }
    return v;
  };
  const auto quiet = trace(false, 1);
  EXPECT_EQ(quiet, std::vector<std::int64_t>(200, 0));
  const auto a = trace(true, 1);
  EXPECT_EQ(a, trace(true, 1));
  EXPECT_NE(a, trace(true, 2));
  EXPECT_NE(a, quiet);
}

TEST(Plant, RegenerationCanTripOverVoltage) {
  const auto brake = [](bool regen) {
    PlantConfig cfg;
    cfg.plant.set(&model::Plant::inertia_load, 2e-3);
    cfg.inertia_ctrl = 2.02e-3;
    cfg.regen.enabled = regen;
    test::Drive d("MC349", cfg);
    d.set(0x6083, 0, 200);
    d.set(0x6085, 0, 20000);
    d.enable(3);
    d.set(0x60FF, 0, 2000);
    d.step(6000);
    EXPECT_NEAR(d.core.supply_voltage(), 48, 1e-9) << "motoring does not charge the link";
    d.cw(0x02);
    d.step(2000);
    return d.read(0x603F);
  };
  EXPECT_EQ(brake(true), 0x3211);
  EXPECT_EQ(brake(false), 0);
}

}  // namespace
}  // namespace mcemu::core
