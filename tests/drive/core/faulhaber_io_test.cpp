// FAULHABER inputs, outputs and limit switches (faulhaber.md §8): 2311h.01/.02 follow the physical
// levels set through the core, polarity 2310h.10, active limit switches stop motion towards them
// (6041h bit 11, 2324h.01 bits 6/7), 2311h.04 switches the outputs two bits per output.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
using test::k_far;

constexpr std::int64_t k_bit_neg = 1 << 7;
constexpr std::int64_t k_bit_pos = 1 << 6;

TEST(FaulhaberInputs, LogicalAndPhysicalStateFollowTheLevels) {
  Drive d("FH_MC5005");
  EXPECT_TRUE(d.core.set_external_input_levels(0b101));
  EXPECT_EQ(d.read(0x2311, 2), 0b101);
  EXPECT_EQ(d.read(0x2311, 1), 0b101);
  d.set(0x2310, 0x10, 0b11);  // DigIn1 and DigIn2 active low
  EXPECT_EQ(d.read(0x2311, 1), 0b110) << "logical = physical XOR polarity, at once";
  EXPECT_TRUE(d.core.set_external_input_level(8, true));
  EXPECT_EQ(d.read(0x2311, 2), 0x85);
  EXPECT_EQ(d.read(0x2311, 1), 0x86);
  d.set(0x2310, 0x10, 0xFFFF);
  EXPECT_EQ(d.read(0x2311, 1), 0x7A) << "only the eight inputs exist";
  EXPECT_FALSE(d.core.set_external_input_levels(1u << 8)) << "no DigIn9";
  EXPECT_FALSE(d.core.set_external_input_level(9, true));
  EXPECT_EQ(d.read(0x2311, 2), 0x85) << "a refused call changes nothing";
  EXPECT_TRUE(d.core.set_external_input_levels(0));
  EXPECT_EQ(d.read(0x2311, 2), 0);
  EXPECT_FALSE(d.od.has_object(0x60FD));
}

TEST(FaulhaberInputs, LevelsSurviveAPowerCycle) {
  Drive d("FH_MC5005");
  d.core.set_external_input_levels(0b1001);
  d.step(3);
  d.core.power_on();
  EXPECT_EQ(d.read(0x2311, 2), 0b1001);
}

TEST(FaulhaberLimitSwitch, ActiveSwitchBlocksMotionTowardsItOnly) {
  Drive d("FH_MC5005");
  d.set(0x2310, 0x01, 4);  // negative switch on DigIn3
  d.set(0x2310, 0x02, 8);  // positive switch on DigIn4
  d.enable(3);
  d.step(10);
  EXPECT_EQ(d.sw() & 0x0800, 0);
  d.core.set_external_input_level(3, true);
  EXPECT_NE(d.read(0x2324, 1) & k_bit_neg, 0);
  EXPECT_EQ(d.read(0x2324, 1) & k_bit_pos, 0);
  EXPECT_NE(d.sw() & 0x0800, 0) << "internal limit active, inside the call";
  d.set(0x60FF, 0, -300);
  d.step(500);
  EXPECT_LE(std::llabs(d.read(0x6064)), 5) << "no motion towards the active negative switch";
  d.set(0x60FF, 0, 300);
  d.step(500);
  EXPECT_GT(d.read(0x6064), 5000) << "away from it is allowed";
  d.core.set_external_input_level(3, false);
  d.core.set_external_input_level(4, true);
  EXPECT_NE(d.read(0x2324, 1) & k_bit_pos, 0);
  const std::int64_t at = d.read(0x6064);
  d.step(500);
  EXPECT_LE(d.read(0x6064), at + 500) << "stopped at 6085h";
  EXPECT_EQ(d.read(0x606C), 0);
  d.core.set_external_input_level(4, false);
  EXPECT_EQ(d.read(0x2324, 1) & (k_bit_pos | k_bit_neg), 0);
  EXPECT_EQ(d.sw() & 0x0800, 0);
  const auto limits = d.of<InternalLimit>();
  EXPECT_GE(limits.size(), 2u);
}

TEST(FaulhaberLimitSwitch, SwitchThatFollowsThePositionStopsTheAxisNearIt) {
  PlantConfig c;
  c.position_switches = {{3, -k_far, -20000}};
  Drive d("FH_MC5005", c);
  d.set(0x2310, 0x01, 4);
  d.enable(3);
  d.set(0x60FF, 0, -600);
  d.step(4000);
  const std::int64_t p = d.read(0x6064);
  EXPECT_LT(p, -20000);
  EXPECT_GT(p, -20200) << "10 rev/s stopped at 3000 rev/s²: about 70 inc past the edge";
  EXPECT_NE(d.sw() & 0x0800, 0);
  d.step(1000);
  EXPECT_EQ(d.read(0x6064), p) << "stays stopped";
  d.set(0x60FF, 0, 600);
  d.step(500);
  EXPECT_GT(d.read(0x6064), -20000);
  EXPECT_EQ(d.sw() & 0x0800, 0);
}

TEST(FaulhaberLimitSwitch, ProfilePositionIntoAnActiveSwitchDoesNotMove) {
  Drive d("FH_MC5005");
  d.set(0x2310, 0x02, 1);  // positive switch on DigIn1
  d.set(0x2310, 0x10, 1);  // active low: with DigIn1 low the switch is active
  d.enable(1);
  EXPECT_NE(d.read(0x2324, 1) & k_bit_pos, 0);
  d.set(0x607A, 0, 20000);
  d.cw(0x1F);
  d.cw(0x0F);
  d.step(1000);
  EXPECT_LE(std::llabs(d.read(0x6064)), 5);
  EXPECT_NE(d.sw() & 0x0800, 0);
  EXPECT_NE(d.sw() & 0x0400, 0) << "cut short like a set-point clamped at a software limit";
  d.set(0x607A, 0, -20000);
  d.cw(0x1F);
  d.cw(0x0F);
  EXPECT_LE(d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 5000), 5000u);
  EXPECT_LE(std::llabs(d.read(0x6064) + 20000), d.read(0x6067));
  d.core.set_external_input_level(1, true);  // switch released
  EXPECT_EQ(d.read(0x2324, 1) & k_bit_pos, 0);
}

TEST(FaulhaberDeviceStatus, SoftLimitBits) {
  Drive d("FH_MC5005");
  d.set(0x607D, 1, -1000);
  d.set(0x607D, 2, 1000);
  d.enable(1);
  EXPECT_EQ(d.read(0x2324, 1) & 0x300, 0);
  d.set(0x607A, 0, 5000);
  d.cw(0x1F);
  d.cw(0x0F);
  ASSERT_LE(d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 3000), 3000u);
  EXPECT_NE(d.read(0x2324, 1) & (1 << 8), 0) << "at the positive software limit";
  d.set(0x607A, 0, -5000);
  d.cw(0x1F);
  d.cw(0x0F);
  ASSERT_LE(d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 3000), 3000u);
  EXPECT_EQ(d.read(0x2324, 1) & (1 << 8), 0);
  EXPECT_NE(d.read(0x2324, 1) & (1 << 9), 0) << "at the negative software limit";
}

struct OutputCase {
  std::uint16_t command;
  std::uint16_t state;  // 2311h.03 after the command, from the state of the previous row
};

TEST(FaulhaberOutputs, TwoBitsPerOutput) {
  Drive d("FH_MC5005");
  EXPECT_EQ(d.read(0x2311, 3), 0);
  // RASCL / MC5005PY values: DigOut1 on FD, off FC, toggle FE; DigOut2 on F7, off F3
  for (const OutputCase c : {OutputCase{0x00FD, 0b01}, OutputCase{0x00F7, 0b11}, OutputCase{0x00FC, 0b10},
                             OutputCase{0x00FE, 0b11}, OutputCase{0x00FE, 0b10}, OutputCase{0x00F3, 0b00},
                             OutputCase{0xFFFF, 0b00}, OutputCase{0x0005, 0b11}, OutputCase{0x0000, 0b00}}) {
    d.set(0x2311, 4, c.command);
    EXPECT_EQ(d.read(0x2311, 3), c.state) << std::hex << c.command;
    EXPECT_EQ(d.read(0x2311, 4), c.command) << "reads return the last value written";
  }
}

}  // namespace
}  // namespace mcemu::core
