// FAULHABER homing (faulhaber.md §7.2): 17/18 on the limit switches of 2310h.01/.02 against a switch
// that follows the position, −1…−4 on a mechanical stop after the 2324h.02 delay, the methods a
// FAULHABER drive does not have.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
using test::homing_bits;
using test::k_far;
using test::start_homing;

TEST(FaulhaberHoming, Method17FindsTheNegativeLimitSwitch) {
  PlantConfig c;
  c.position_switches = {{3, -k_far, -20000}};  // DigIn3 high while the axis is at or below −20000
  Drive d("FH_MC5005", c);
  d.set(0x2310, 0x01, 4);  // AN165 Example A: "this is bit coded - here input 3"
  d.enable(6);
  start_homing(d, 17);
  EXPECT_EQ(homing_bits(d), 0x0000) << "in progress";
  bool saw_switch = false;
  std::int64_t lowest = 0;
  const auto ms = d.step_until(
      [&] {
        saw_switch = saw_switch || (d.read(0x2324, 1) & (1 << 7)) != 0;
        lowest = std::min(lowest, d.core.raw_position_inc());
        return homing_bits(d) == 0x1400;
      },
      20000);
  ASSERT_LE(ms, 20000u);
  EXPECT_TRUE(saw_switch) << "2324h.01 bit 7 while the switch was active";
  EXPECT_LT(lowest, -20000) << "the axis went onto the switch";
  EXPECT_NEAR(static_cast<double>(d.core.raw_position_inc()), -20000, 30) << "reference at the switch edge";
  EXPECT_LE(std::llabs(d.read(0x6064)), 30) << "6064h = 607Ch = 0 at the reference";
  ASSERT_EQ(d.of<HomingFinished>().size(), 1u);
  EXPECT_TRUE(d.of<HomingFinished>()[0].ok);
  // AN165 continues in PP: a move away from the switch
  d.cw(0x0F);
  d.set(0x6060, 0, 1);
  d.set(0x607A, 0, 10000);
  d.cw(0x1F);
  d.cw(0x0F);
  EXPECT_LE(d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 5000), 5000u);
  EXPECT_LE(std::llabs(d.read(0x6064) - 10000), d.read(0x6067));
}

TEST(FaulhaberHoming, Method18FindsThePositiveLimitSwitch) {
  PlantConfig c;
  c.position_switches = {{5, 30000, k_far}};
  Drive d("FH_MCS", c);
  d.set(0x2310, 0x02, 0x10);
  d.set(0x607C, 0, 7);
  d.enable(6);
  start_homing(d, 18);
  ASSERT_LE(d.step_until([&] { return homing_bits(d) == 0x1400; }, 20000), 20000u);
  EXPECT_NEAR(static_cast<double>(d.core.raw_position_inc()), 30000, 30);
  EXPECT_LE(std::llabs(d.read(0x6064) - 7), 30);
}

TEST(FaulhaberHoming, SwitchMethodWithoutASwitchIsAnError) {
  Drive d("FH_MC5005");
  d.enable(6);
  start_homing(d, 17);
  EXPECT_EQ(homing_bits(d), 0x2000);
}

struct BlockCase {
  std::int8_t method;
  std::int64_t stop;
};

class FaulhaberBlockHoming : public ::testing::TestWithParam<BlockCase> {};

TEST_P(FaulhaberBlockHoming, ReferenceAtTheStopAfterTheDelay) {
  const auto& bc = GetParam();
  for (const std::int64_t delay : {200, 500}) {
    PlantConfig c;
    c.plant.set(&model::Plant::stops_inc, StopRange{-50000, 50000});
    Drive d("FH_MC5010", c);
    d.set(0x2324, 0x02, delay);
    d.set(0x60E0, 0, 500);  // AN165's master example homes with reduced torque limits
    d.set(0x60E1, 0, 500);
    d.enable(6);
    start_homing(d, bc.method);
    std::uint64_t at_stop = 0;
    const auto ms = d.step_until(
        [&] {
          if (at_stop == 0 && d.core.raw_position_inc() == bc.stop) at_stop = d.core.time_ms();
          return homing_bits(d) == 0x1400;
        },
        20000);
    ASSERT_LE(ms, 20000u) << int(bc.method);
    ASSERT_NE(at_stop, 0u);
    const auto waited = static_cast<std::int64_t>(d.core.time_ms() - at_stop);
    EXPECT_GE(waited, delay) << int(bc.method);
    EXPECT_LE(waited, delay + 30) << int(bc.method);
    EXPECT_EQ(d.core.raw_position_inc(), bc.stop);
    EXPECT_EQ(d.read(0x6064), 0);
    EXPECT_EQ(d.core.fault_bits(), 0u) << "a block while homing is no fault";
    EXPECT_TRUE(d.of<Emcy>().empty());
  }
}

INSTANTIATE_TEST_SUITE_P(Spec, FaulhaberBlockHoming,
                         ::testing::Values(BlockCase{-1, -50000}, BlockCase{-2, 50000}, BlockCase{-3, -50000},
                                           BlockCase{-4, 50000}));

TEST(FaulhaberHoming, MethodsTheDriveDoesNotHaveAreErrors) {
  for (int method : {-19, -18, -5, 1, 19, 20, 21, 22, 23, 34}) {
    Drive d("FH_MC5005");
    d.enable(6);
    start_homing(d, static_cast<std::int8_t>(method));
    EXPECT_EQ(homing_bits(d), 0x2000) << method;
  }
  for (int method : {0, 35, 37}) {
    Drive d("FH_MC5005");
    d.enable(6);
    start_homing(d, static_cast<std::int8_t>(method));
    d.step(10);
    EXPECT_EQ(homing_bits(d), 0x1400) << method;
  }
  Drive mc("MC349");
  mc.enable(6);
  start_homing(mc, -1);
  EXPECT_EQ(homing_bits(mc), 0x2000) << "−1…−4 are FAULHABER methods";
}

}  // namespace
}  // namespace mcemu::core
