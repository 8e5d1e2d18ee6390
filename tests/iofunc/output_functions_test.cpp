// The pure output evaluation (iofunc.md §5.2–§5.5) as tables: one row per case, including every
// row of the bit-coded feedback table of §5.5.
#include "iofunc/output_functions.hpp"

#include <gtest/gtest.h>

#include <string>

namespace mcemu::iofunc {
namespace {

core::Scaling factory_scaling() { return core::Scaling(core::FactorGroup{}, model::Kind::rotary, core::AccelUnit{}); }

struct LevelCase {
  const char* name;
  OutputConfig cfg;
  DriveSnapshot s;
  bool expected;
};

DriveSnapshot with(std::uint16_t sw, std::uint32_t mfr = 0, std::int64_t user = 0) {
  DriveSnapshot s;
  s.statusword = sw;
  s.mfr_status = mfr;
  s.position_user = user;
  return s;
}

OutputConfig fn(int function, std::uint16_t config, std::int64_t r_pos = 1000, std::int64_t l_pos = -1000,
                std::int64_t r_dist = 100, std::int64_t l_dist = 100) {
  return OutputConfig{function, config, r_pos, l_pos, r_dist, l_dist};
}

class Level : public ::testing::TestWithParam<LevelCase> {};

TEST_P(Level, OfOutput1) {
  const LevelCase& c = GetParam();
  EXPECT_EQ(output_level(c.cfg, 1, c.s, factory_scaling()), c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    Functions, Level,
    ::testing::Values(
        // function 0 has no computed level; unknown functions neither
        LevelCase{"f0_manual", fn(0, 0xFFFF), with(0xFFFF), false},
        LevelCase{"f7_unknown", fn(7, 0xFFFF), with(0xFFFF), false},
        // 1: any selected statusword bit
        LevelCase{"f1_bit10_set", fn(1, 0x0400), with(0x0427), true},
        LevelCase{"f1_bit10_clear", fn(1, 0x0400), with(0x0027), false},
        LevelCase{"f1_any_of_mask", fn(1, 0x0408), with(0x0008), true},
        LevelCase{"f1_mask_0", fn(1, 0), with(0xFFFF), false},
        // 2: 1002h bits 0–15
        LevelCase{"f2_bit9", fn(2, 0x0200), with(0x0008, 0x200), true},
        LevelCase{"f2_other_bit", fn(2, 0x0200), with(0x0008, 0x100), false},
        LevelCase{"f2_warning_bit16_not_visible", fn(2, 0xFFFF), with(0x0040, 0x10000), false},
        // 3: limit monitor, inclusive bounds
        LevelCase{"f3_right_low_edge", fn(3, 1), with(0x27, 0, 1000), true},
        LevelCase{"f3_right_high_edge", fn(3, 1), with(0x27, 0, 1100), true},
        LevelCase{"f3_right_beyond", fn(3, 1), with(0x27, 0, 1101), false},
        LevelCase{"f3_right_below", fn(3, 1), with(0x27, 0, 999), false},
        LevelCase{"f3_right_negative_distance", fn(3, 1, 1000, -1000, -100), with(0x27, 0, 900), true},
        LevelCase{"f3_right_negative_distance_above", fn(3, 1, 1000, -1000, -100), with(0x27, 0, 1001), false},
        LevelCase{"f3_left_high_edge", fn(3, 2), with(0x27, 0, -1000), true},
        LevelCase{"f3_left_low_edge", fn(3, 2), with(0x27, 0, -1100), true},
        LevelCase{"f3_left_beyond", fn(3, 2), with(0x27, 0, -1101), false},
        LevelCase{"f3_left_negative_distance", fn(3, 2, 1000, -1000, 100, -100), with(0x27, 0, -900), true},
        LevelCase{"f3_left_disabled", fn(3, 1), with(0x27, 0, -1050), false},
        LevelCase{"f3_both", fn(3, 3), with(0x27, 0, -1050), true},
        LevelCase{"f3_none_selected", fn(3, 0xFFFC), with(0x27, 0, 1050), false},
        // 5: drive OK
        LevelCase{"f5_switched_off_ok", fn(5, 0), with(0x0040), true},
        LevelCase{"f5_fault", fn(5, 0), with(0x0008, 0x200), false},
        LevelCase{"f5_warning", fn(5, 0), with(0x00C0, 0x10000), false},
        LevelCase{"f5_error_bit_without_fault_state", fn(5, 0), with(0x0027, 0x1), false},
        LevelCase{"f5_reserved_bits_14_15_ignored", fn(5, 0), with(0x0027, 0xC000), true}),
    [](const auto& p) { return std::string(p.param.name); });

// §5.4: held(R) with windows .05/.06, negative windows count as 0.
struct ReachedCase {
  const char* name;
  std::uint16_t config;
  std::int64_t position_inc;
  std::int64_t right;
  std::int64_t left;
  bool expected;
};

class PositionReached : public ::testing::TestWithParam<ReachedCase> {};

TEST_P(PositionReached, Held) {
  const ReachedCase& c = GetParam();
  DriveSnapshot s = with(0x0027);
  s.position_inc = c.position_inc;
  s.general_reference_inc = 5000;
  s.result1[2] = 4500;  // IN3
  const OutputConfig cfg = fn(4, c.config, 0, 0, c.right, c.left);
  EXPECT_EQ(output_level(cfg, 1, s, factory_scaling()), c.expected);
  // function 6 is the same AND drive OK
  EXPECT_EQ(output_level(fn(6, c.config, 0, 0, c.right, c.left), 1, s, factory_scaling()), c.expected);
  s.statusword = 0x0008;
  EXPECT_FALSE(output_level(fn(6, c.config, 0, 0, c.right, c.left), 1, s, factory_scaling()));
}

INSTANTIATE_TEST_SUITE_P(Windows, PositionReached,
                         ::testing::Values(ReachedCase{"general_exact", 0, 5000, 20, 20, true},
                                           ReachedCase{"general_right_edge", 0, 5020, 20, 20, true},
                                           ReachedCase{"general_right_out", 0, 5021, 20, 20, false},
                                           ReachedCase{"general_left_edge", 0, 4980, 20, 20, true},
                                           ReachedCase{"general_left_out", 0, 4979, 20, 20, false},
                                           ReachedCase{"one_sided_window", 0, 4999, 50, 0, false},
                                           ReachedCase{"negative_window_is_0", 0, 4999, 50, -10, false},
                                           ReachedCase{"input3_held", 3, 4510, 20, 20, true},
                                           ReachedCase{"input3_not_held", 3, 4521, 20, 20, false},
                                           ReachedCase{"input1_result_0", 1, 0, 20, 20, true},
                                           ReachedCase{"config_11_low", 11, 0, 20, 20, false},
                                           ReachedCase{"config_254_low", 254, 0, 20, 20, false}),
                         [](const auto& p) { return std::string(p.param.name); });

// Windows are user units converted by the core's scaling (here 1 usr = 8192/9 inc).
TEST(PositionReachedScaling, WindowsInUserUnits) {
  core::FactorGroup fg;
  fg.gear_motor = 5;
  fg.feed = 360;
  const core::Scaling sc(fg, model::Kind::rotary, core::AccelUnit{});
  DriveSnapshot s = with(0x0027);
  s.general_reference_inc = 0;
  s.position_inc = 910;  // inc(1 usr) = 910
  EXPECT_TRUE(output_level(fn(4, 0, 0, 0, 1, 1), 1, s, sc));
  s.position_inc = 911;
  EXPECT_FALSE(output_level(fn(4, 0, 0, 0, 1, 1), 1, s, sc));
}

// §5.4 rotary operation: d is reduced into [−⌊P/2⌋, P − ⌊P/2⌋) first.
TEST(PositionReachedRotary, DistanceReducedByThePeriod) {
  DriveSnapshot s = with(0x0027);
  s.rotary_period_inc = 65536;
  s.general_reference_inc = 100;
  s.position_inc = 100 + 3 * 65536 + 15;
  EXPECT_TRUE(output_level(fn(4, 0, 0, 0, 20, 20), 1, s, factory_scaling()));
  s.position_inc = 100 - 2 * 65536 - 15;
  EXPECT_TRUE(output_level(fn(4, 0, 0, 0, 20, 20), 1, s, factory_scaling()));
  s.position_inc = 100 + 32768;
  EXPECT_FALSE(output_level(fn(4, 0, 0, 0, 20, 20), 1, s, factory_scaling()));
  s.rotary_period_inc.reset();
  s.position_inc = 100 + 65536;
  EXPECT_FALSE(output_level(fn(4, 0, 0, 0, 20, 20), 1, s, factory_scaling()));
}

// §5.5: every row of the code table. Candidate n holds n·10000; the drive stands at code·10000.
struct CodeRow {
  int code;
  bool out1, out2, out3, out4;
};

class BitCoded : public ::testing::TestWithParam<CodeRow> {};

TEST_P(BitCoded, CodeTable) {
  const CodeRow& row = GetParam();
  DriveSnapshot s = with(0x0027);
  s.candidates = 0x3FF;
  for (int n = 1; n <= 10; ++n) s.result1[static_cast<std::size_t>(n - 1)] = n * 10000;
  s.position_inc = row.code == 0 ? -50000 : row.code * 10000;
  const OutputConfig cfg = fn(4, 255, 0, 0, 20, 20);
  const auto sc = factory_scaling();
  EXPECT_EQ(output_level(cfg, 1, s, sc), row.out1);
  EXPECT_EQ(output_level(cfg, 2, s, sc), row.out2);
  EXPECT_EQ(output_level(cfg, 3, s, sc), row.out3);
  EXPECT_EQ(output_level(cfg, 4, s, sc), row.out4);
}

INSTANTIATE_TEST_SUITE_P(Table, BitCoded,
                         ::testing::Values(CodeRow{0, false, false, false, false},
                                           CodeRow{1, true, false, false, false}, CodeRow{2, false, true, false, false},
                                           CodeRow{3, true, true, false, false}, CodeRow{4, false, false, true, false},
                                           CodeRow{5, true, false, true, false}, CodeRow{6, false, true, true, false},
                                           CodeRow{7, true, true, true, false}, CodeRow{8, false, false, false, true},
                                           CodeRow{9, true, false, false, true}, CodeRow{10, false, true, false, true}),
                         [](const auto& p) { return "code_" + std::to_string(p.param.code); });

// The smallest held candidate wins; non-candidates are ignored (§5.5).
TEST(BitCodedCandidates, SmallestHeldCandidateWins) {
  DriveSnapshot s = with(0x0027);
  s.position_inc = 0;
  s.candidates = 0b0110;  // IN2 and IN3, both still at result 0
  const OutputConfig cfg = fn(4, 255, 0, 0, 20, 20);
  EXPECT_FALSE(output_level(cfg, 1, s, factory_scaling()));
  EXPECT_TRUE(output_level(cfg, 2, s, factory_scaling()));
  s.result1[1] = 4500;  // IN2 moved away: IN3 is the smallest that holds 0
  EXPECT_TRUE(output_level(cfg, 1, s, factory_scaling()));
  EXPECT_TRUE(output_level(cfg, 2, s, factory_scaling()));
  s.candidates = 0;
  EXPECT_FALSE(output_level(cfg, 1, s, factory_scaling()));
  EXPECT_FALSE(output_level(cfg, 2, s, factory_scaling()));
}

}  // namespace
}  // namespace mcemu::iofunc
