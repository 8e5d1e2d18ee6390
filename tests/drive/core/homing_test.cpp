// Homing mode (drive-core.md §9, §15 item 13): position set (35/37), block homing against a
// configured stop (−18/−19), home and limit switch methods (17, 19–22), errors, halt, RABBIT.
#include <gtest/gtest.h>

#include <cmath>

#include "drive/helpers/helpers.hpp"
#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
using test::homing_bits;
using test::start_homing;

TEST(Homing, Method35SetsPositionAtOnceWithTenMsPulse) {
  Drive d;
  d.enable(6);
  d.step(5);
  EXPECT_EQ(homing_bits(d), 0x0400) << "not started: 001 — ros2_canopen expects reached before the start";
  d.set(0x607C, 0, 100);
  start_homing(d, 35);
  EXPECT_EQ(d.read(0x6064), 100);
  EXPECT_EQ(homing_bits(d), 0x0000) << "in progress right after the start";
  d.step(9);
  EXPECT_EQ(homing_bits(d), 0x0000);
  d.step();
  EXPECT_EQ(homing_bits(d), 0x1400) << "attained + reached at the end of the 10th step";
  ASSERT_EQ(d.of<HomingFinished>().size(), 1u);
  EXPECT_TRUE(d.of<HomingFinished>()[0].ok);
  EXPECT_EQ(d.read(0x6064), 100);
  EXPECT_EQ(d.read(0x60FC), d.read(0x6063)) << "no motion";
}

TEST(Homing, Method37AndMethod0) {
  Drive d;
  d.enable(6);
  d.set(0x607C, 0, -5);
  start_homing(d, 37);
  EXPECT_EQ(d.read(0x6064), -5);
  d.step(10);
  EXPECT_EQ(homing_bits(d), 0x1400);
  d.set(0x607C, 0, 77);
  d.cw(0x0F);
  start_homing(d, 0);
  EXPECT_EQ(d.read(0x6064), -5) << "method 0 does not change the position";
  d.step(10);
  EXPECT_EQ(homing_bits(d), 0x1400);
}

TEST(Homing, UnsupportedMethodsAreErrorsAtStart) {
  for (int method : {1, 18, 23, 30, 34, -20}) {
    Drive d;
    d.enable(6);
    start_homing(d, static_cast<std::int8_t>(method));
    EXPECT_EQ(homing_bits(d), 0x2000) << method;
    EXPECT_FALSE(d.of<HomingFinished>().at(0).ok);
    d.step(50);
    EXPECT_EQ(d.read(0x60FC), 0);
    EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  }
}

TEST(Homing, Method18WhenEnabledByConfig) {
  PlantConfig cfg;
  cfg.homing.enable_method_18 = true;
  cfg.position_switches.push_back({2, 40000, 1000000000});
  Drive d("MC349", cfg);
  d.set(0x60B8, 0, 0x200);  // right limit switch = IN2
  d.set(0x6099, 2, 10);
  d.enable(6);
  start_homing(d, 18);
  d.step_until([&] { return homing_bits(d) != 0; }, 20000);
  EXPECT_EQ(homing_bits(d), 0x1400);
  EXPECT_NEAR(static_cast<double>(d.core.home_offset_inc()), 40000, 15);
}

TEST(Homing, BlockHomingNegativeAgainstConfiguredStop) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::stops_inc, StopRange{-100000, 1000000000});
  Drive d("MC349", cfg);
  d.set(0x607C, 0, 250);
  d.set(0x6073, 0, 300);  // reduced torque
  d.enable(6);
  start_homing(d, -19);
  EXPECT_EQ(homing_bits(d), 0);
  d.step();
  EXPECT_EQ(homing_bits(d), 0) << "target reached drops at the start and stays low while searching";
  const std::uint64_t ms = d.step_until([&] { return homing_bits(d) != 0; }, 20000);
  EXPECT_LT(ms, 20000u);
  EXPECT_EQ(homing_bits(d), 0x1400);
  EXPECT_EQ(d.core.raw_position_inc(), -100000);
  EXPECT_EQ(d.read(0x6064), 250);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(d.read(0x1002), 0) << "block homing never raises a stroke fault";
  d.step(1000);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_LT(std::llabs(d.read(0x6078)), 50) << "no longer pushing after the reference";
}

TEST(Homing, BlockHomingPositive) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::stops_inc, StopRange{-1000000000, 70000});
  Drive d("MC349", cfg);
  d.enable(6);
  start_homing(d, -18);
  d.step_until([&] { return homing_bits(d) != 0; }, 20000);
  EXPECT_EQ(homing_bits(d), 0x1400);
  EXPECT_EQ(d.core.raw_position_inc(), 70000);
  EXPECT_EQ(d.read(0x6064), 0);
}

struct SwitchCase {
  std::int8_t method;
  std::int64_t from, to;  // switch active range (raw inc)
  std::int64_t start;     // power-on position
  std::int64_t edge;      // expected reference (raw), within 2 inc
};

class SwitchHoming : public ::testing::TestWithParam<SwitchCase> {};

TEST_P(SwitchHoming, ReferenceAtTheSwitchEdge) {
  const auto c = GetParam();
  PlantConfig cfg;
  cfg.position_switches.push_back({1, c.from, c.to});
  cfg.plant.set(&model::Plant::power_on_position_inc, c.start);
  Drive d("MC349_AE", cfg);  // absolute: 6063h = raw at power on
  d.set(0x60B8, 0, c.method == 17 ? 0x10 : 0x01);
  d.set(0x6099, 2, 1);  // 1 rpm: 1.09 inc per step
  d.set(0x607C, 0, 0);
  d.enable(6);
  start_homing(d, c.method);
  const std::uint64_t ms = d.step_until([&] { return homing_bits(d) != 0; }, 60000);
  ASSERT_LT(ms, 60000u);
  EXPECT_EQ(homing_bits(d), 0x1400);
  EXPECT_NEAR(static_cast<double>(d.core.home_offset_inc()), static_cast<double>(c.edge), 2);
  EXPECT_EQ(d.read(0x6063), d.core.raw_position_inc() - d.core.home_offset_inc());
}

// Switch IN1 high on [50000, 1e9] ("positive side") or [-1e9, -50000] ("negative side").
INSTANTIATE_TEST_SUITE_P(
    Methods, SwitchHoming,
    ::testing::Values(SwitchCase{19, 50000, 1000000000, 0, 50000},          // inactive: +fast, −slow to edge
                      SwitchCase{19, 50000, 1000000000, 80000, 50000},      // active at start: −slow
                      SwitchCase{20, 50000, 1000000000, 80000, 50000},      // active: −fast, +slow to edge
                      SwitchCase{20, 50000, 1000000000, 0, 50000},          // inactive: +slow
                      SwitchCase{21, -1000000000, -50000, 0, -50000},       // mirrored 19
                      SwitchCase{22, -1000000000, -50000, -80000, -50000},  // mirrored 20
                      SwitchCase{17, -1000000000, -50000, 0, -50000}));     // negative limit switch

TEST(Homing, SwitchMethodWithoutSwitchAssignmentIsError) {
  Drive d;
  d.enable(6);
  start_homing(d, 19);
  EXPECT_EQ(homing_bits(d), 0x2000);
}

TEST(Homing, SearchTimeoutIsError) {
  PlantConfig cfg;
  cfg.homing.max_search_ms = 500;
  Drive d("MC349", cfg);
  d.set(0x60B8, 0, 1);
  d.enable(6);
  start_homing(d, 19);
  d.step(499);
  EXPECT_EQ(homing_bits(d), 0);
  d.step(2);
  EXPECT_EQ(homing_bits(d), 0x2000);
  d.step(2000);
  EXPECT_EQ(d.read(0x606B), 0) << "decelerates and holds";
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
}

TEST(Homing, HaltInterrupts) {
  Drive d;
  d.set(0x60B8, 0, 1);
  d.enable(6);
  start_homing(d, 19);
  d.step(200);
  d.cw(0x11F);
  EXPECT_EQ(homing_bits(d), 0x0400) << "interrupted: 001";
  d.step(2000);
  EXPECT_EQ(d.read(0x606B), 0);
  d.cw(0x01F);
  d.step(100);
  EXPECT_EQ(homing_bits(d), 0x0400) << "releasing halt does not resume";
}

TEST(Homing, BlockDuringMaskedSwitchSearchIsHomingError) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::stops_inc, StopRange{-1000000000, 30000});
  Drive d("MC349", cfg);
  d.set(0x60B8, 0, 1);
  d.set(0x3401, 0x1A, 15);
  d.enable(6);
  start_homing(d, 19);
  d.step_until([&] { return homing_bits(d) != 0; }, 20000);
  EXPECT_EQ(homing_bits(d), 0x2000);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
}

TEST(Homing, BlockDuringUnmaskedSwitchSearchIsStrokeFault) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::stops_inc, StopRange{-1000000000, 30000});
  Drive d("MC349", cfg);
  d.set(0x60B8, 0, 1);
  d.enable(6);
  start_homing(d, 19);
  d.step_until([&] { return d.core.state() == PdsState::fault; }, 20000);
  EXPECT_EQ(d.read(0x603F), 0x7121);
}

TEST(Homing, RabbitHomesBy35Only) {
  Drive d("MCFLAT");
  d.enable(6);
  start_homing(d, 37);
  EXPECT_EQ(homing_bits(d), 0x2000);
  d.set(0x607C, 0, 10);
  d.cw(0x0F);
  start_homing(d, 35);
  EXPECT_EQ(d.read(0x6064), 10);
  d.step(10);
  EXPECT_EQ(homing_bits(d), 0x1400);
}

TEST(Homing, SetHomeHereOutsideOperationAndRefusedInFault) {
  Drive d;
  d.step();
  d.set(0x607C, 0, 360);
  EXPECT_EQ(d.core.set_home_here(), od::AbortCode::none);
  EXPECT_EQ(d.read(0x6064), 360);
  d.core.inject(FaultCause::sensor);
  d.step();
  d.set(0x607C, 0, 0);
  EXPECT_EQ(d.core.set_home_here(), od::AbortCode::device_state);
  EXPECT_EQ(d.read(0x6064), 360);
}

TEST(Homing, GoHomeHelper) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::stops_inc, StopRange{-100000, 1000000000});
  Drive d("MC349", cfg);
  d.step();
  helpers::DriveRef ref{d.core, d.od, od::Origin::refgo};
  EXPECT_EQ(helpers::go_home(ref, 35, 1000, 1000, 7), od::AbortCode::none);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled) << "REF35 outside OE does not enable";
  EXPECT_EQ(d.read(0x6064), 7);
  EXPECT_EQ(helpers::go_home(ref, -19, 500, 1000, 0), od::AbortCode::none);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled) << "AUTOENABLE";
  EXPECT_EQ(d.read(0x6061), 6);
  d.step_until([&] { return homing_bits(d) != 0; }, 30000);
  EXPECT_EQ(homing_bits(d), 0x1400);
  EXPECT_EQ(d.read(0x6064), 0);
}

}  // namespace
}  // namespace mcemu::core
