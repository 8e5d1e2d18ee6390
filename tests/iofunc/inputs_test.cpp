// Inputs, edges and the simulation objects (iofunc.md §2.1, §3, §4.13, §6): tests IN-V and IN-C,
// the abort tables of §4.1/§4.13/§5.1, and the cross-cutting edge rules (power on, pulses between
// steps, queue order, bulk load).
#include <gtest/gtest.h>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

TEST(VirtualInputs, InV) {
  Rig rig;
  run_rows(rig, {
                    {"W(3512.01,0x0300), IN1 counts both edges; P(1,1); W(3510.01,0x20000)",
                     [](Rig& r) {
                       r.W(0x3512, 1, 0x0300);
                       r.W(0x3511, 1, 0x0303);
                       r.P(1, true);
                       r.W(0x3510, 1, 0x20000);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.inputs(), 0x30000u);
                       EXPECT_EQ((r.inputs() >> 17) & 1, 1u);  // TI2 answers 1
                     }},
                    {"step(1)", [](Rig& r) { r.step(); },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3512, 3), 1);
                       EXPECT_EQ(r.R(0x3511, 3), 1);
                     }},
                    {"W(3510.01,0x20000) again, step(1)",
                     [](Rig& r) {
                       r.W(0x3510, 1, 0x20000);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3512, 3), 1); }},
                    {"W(3510.01,0x10000) (IN1 physically high), step(1)",
                     [](Rig& r) {
                       r.W(0x3510, 1, 0x10000);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.inputs(), 0x10000u);
                       EXPECT_EQ(r.R(0x3511, 3), 1);  // no IN1 edge
                       EXPECT_EQ(r.R(0x3512, 3), 1);
                     }},
                    {"P(1,0) while virtual IN1 is set",
                     [](Rig& r) {
                       r.P(1, false);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.inputs(), 0x10000u);
                       EXPECT_EQ(r.R(0x3511, 3), 1);
                     }},
                    {"W(3510.01,0)", [](Rig& r) { r.W(0x3510, 1, 0); },
                     [](Rig& r) {
                       EXPECT_EQ(r.inputs(), 0u);
                       r.step();
                       EXPECT_EQ(r.R(0x3511, 3), 2);  // the falling edge of IN1 counts
                     }},
                    {"W(3510.01,0x0400FFFF)", [](Rig& r) { r.W(0x3510, 1, 0x0400FFFF); },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3510, 1), 0x0400FFFF);
                       EXPECT_EQ(r.inputs(), 0u);
                     }},
                });
}

// Inputs without a pin cannot be set physically, but their virtual bit works (§2.1).
TEST(VirtualInputs, PinlessInputsOnlyVirtually) {
  Rig rig;
  EXPECT_FALSE(rig.core.set_external_input_level(5, true));
  EXPECT_EQ(rig.inputs(), 0u);
  rig.W(0x3515, 1, 0x0300);
  rig.W(0x3510, 1, 1 << 20);
  EXPECT_EQ(rig.inputs(), 1u << 20);
  rig.step();
  EXPECT_EQ(rig.R(0x3515, 3), 1);
}

TEST(InputFunctionCommand, InC) {
  Rig rig;
  run_rows(rig, {
                    {"W(3513.01,0), .05 = 0, .08 = -2000, .06 = 500; W(3510.02,0x0304), step(1)",
                     [](Rig& r) {
                       r.W(0x3513, 1, 0);
                       r.W(0x3513, 5, 0);
                       r.W(0x3513, 8, -2000);
                       r.W(0x3513, 6, 500);
                       r.W(0x3510, 2, 0x0304);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x607A), -2000);
                       EXPECT_EQ(r.R(0x3513, 3), -2000);
                       EXPECT_EQ(r.R(0x3513, 4), 1);
                       EXPECT_EQ(r.R(0x3513, 1), 0);
                       EXPECT_EQ(r.R(0x3510, 2), 0x0304);
                       EXPECT_EQ(r.R(0x6081), 500);
                     }},
                    {"W(3510.02,0x0300), step(10)",
                     [](Rig& r) {
                       r.W(0x3510, 2, 0x0300);
                       r.step(10);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3513, 4), 1);
                       EXPECT_EQ(r.R(0x3510, 2), 0x0300);
                     }},
                });
}

// A command is applied at the next step, with the record's timer (§4.13).
TEST(InputFunctionCommand, QueuedAndDelayed) {
  Rig rig;
  rig.W(0x3517, 1, 0x0303);  // .01 is not consulted
  rig.W(0x3517, 5, 100);
  rig.W(0x3517, 8, 1234);
  rig.W(0x3510, 2, 0x0704);
  EXPECT_EQ(rig.R(0x607A), 0);
  rig.step(100);
  EXPECT_EQ(rig.R(0x3517, 4), 0);
  rig.step();
  EXPECT_EQ(rig.R(0x607A), 1234);
  EXPECT_EQ(rig.R(0x3517, 4), 1);
  EXPECT_EQ(rig.R(0x3517, 1), 0x0303);
  rig.W(0x3510, 2, 0x0703);  // counter through the command
  rig.step();
  EXPECT_EQ(rig.R(0x3517, 3), 1235);
}

struct AbortCase {
  const char* name;
  std::uint16_t index;
  std::uint8_t sub;
  std::int64_t value;
  od::AbortCode expected;
};

class WriteRules : public ::testing::TestWithParam<AbortCase> {};

TEST_P(WriteRules, AbortCodes) {
  const AbortCase c = GetParam();
  Rig rig;
  const std::int64_t before = rig.R(c.index, c.sub);
  EXPECT_EQ(rig.try_write(c.index, c.sub, c.value), c.expected);
  if (c.expected != od::AbortCode::none) {
    EXPECT_EQ(rig.R(c.index, c.sub), before);
  }
  rig.step(10);
  EXPECT_EQ(rig.sw() & 0x6F, 0x40);  // no command ran
}

constexpr auto k_invalid = od::AbortCode::invalid_value;
constexpr auto k_ok = od::AbortCode::none;

INSTANTIATE_TEST_SUITE_P(Tables, WriteRules,
                         ::testing::Values(AbortCase{"cmd_yy_out_of_range_0B04", 0x3510, 2, 0x0B04, k_invalid},
                                           AbortCase{"cmd_zz_0C", 0x3510, 2, 0x030C, k_invalid},
                                           AbortCase{"cmd_zz_9_level", 0x3510, 2, 0x0309, k_invalid},
                                           AbortCase{"cmd_zz_10_jog", 0x3510, 2, 0x030A, k_invalid},
                                           AbortCase{"cmd_zz_11_jog", 0x3510, 2, 0x030B, k_invalid},
                                           AbortCase{"cmd_yy_0", 0x3510, 2, 0x0004, k_invalid},
                                           AbortCase{"cmd_noop_0000", 0x3510, 2, 0x0000, k_ok},
                                           AbortCase{"cmd_noop_any_yy_0B00", 0x3510, 2, 0x0B00, k_ok},
                                           AbortCase{"fn_high_byte_0C", 0x3511, 1, 0x0C00, k_invalid},
                                           AbortCase{"fn_low_byte_0C", 0x351A, 1, 0x000C, k_invalid},
                                           AbortCase{"fn_0B0B", 0x3514, 1, 0x0B0B, k_ok},
                                           AbortCase{"out_fn_7", 0x3611, 1, 7, k_invalid},
                                           AbortCase{"out_fn_6", 0x3614, 1, 6, k_ok}),
                         [](const auto& p) { return std::string(p.param.name); });

// Levels already high at power on give no edge (§3); levels do count for Teach from the first step.
TEST(Edges, NoEdgeAtPowerOn) {
  Rig rig;
  rig.W(0x3511, 1, 0x0303);
  rig.W(0x3514, 1, 0x0008);
  rig.P(1, true);
  rig.P(4, true);
  rig.io.power_on();  // power cycle: injected input levels survive
  rig.step(5);
  EXPECT_EQ(rig.R(0x3511, 3), 0);
  EXPECT_TRUE(rig.io.teach_active());
  rig.P(1, false);
  rig.step();
  EXPECT_EQ(rig.R(0x3511, 3), 1);
}

// A 0 → 1 → 0 pulse between two steps queues both edges (§3).
TEST(Edges, PulseBetweenStepsGivesTwoEdges) {
  Rig rig;
  rig.W(0x3511, 1, 0x0303);
  rig.P(1, true);
  rig.P(1, false);
  EXPECT_EQ(rig.R(0x3511, 3), 0);  // applied at the next step, not in the write
  rig.step();
  EXPECT_EQ(rig.R(0x3511, 3), 2);
}

// Edges found in the same sample apply in ascending input order; the later move wins (§6 rule 6).
TEST(Edges, SimultaneousEdgesInInputOrder) {
  Rig rig;
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 8, 1000);
  rig.W(0x3512, 1, 0x0400);
  rig.W(0x3512, 8, 2000);
  rig.W(0x3510, 1, 0x30000);
  rig.step();
  EXPECT_EQ(rig.R(0x607A), 2000);
  EXPECT_EQ(rig.R(0x3511, 4), 1);
  EXPECT_EQ(rig.R(0x3512, 4), 1);
}

// Timers fire in deadline order, ties by input number.
TEST(Edges, TimersInDeadlineOrder) {
  Rig rig;
  rig.W(0x3512, 1, 0x0400);
  rig.W(0x3512, 5, 10);
  rig.W(0x3512, 8, 2000);
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 5, 20);
  rig.W(0x3511, 8, 1000);
  rig.W(0x3510, 1, 0x30000);
  rig.step(11);
  EXPECT_EQ(rig.R(0x607A), 2000);
  rig.step(10);
  EXPECT_EQ(rig.R(0x607A), 1000);
}

// After a bulk load of the OD (factory reset) timers, jog ownership and candidacy are cleared.
TEST(BulkLoad, ClearsTimersJogAndCandidates) {
  Rig rig("MC632");
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 5, 500);
  rig.W(0x3515, 1, 0x0A0A);
  rig.W(0x3512, 1, 0x0400);
  rig.W(0x3510, 2, 0x0206);  // IN2 runs a relative move: a candidate by execution too
  rig.step();
  rig.P(5, true);
  rig.P(1, true);
  rig.step();
  ASSERT_TRUE(rig.io.jog_owner().has_value());
  ASSERT_TRUE(rig.io.timer_deadline(1).has_value());
  const std::vector<od::StoredValue> factory = {{0x3511, 1, od::Value{std::int64_t{0}}},
                                                {0x3512, 1, od::Value{std::int64_t{0}}},
                                                {0x3515, 1, od::Value{std::int64_t{0}}}};
  ASSERT_TRUE(rig.od.load_values(factory).empty());
  ASSERT_EQ(rig.io.feedback_candidates(), 0x2);  // IN2 by execution only
  rig.io.after_bulk_load();
  EXPECT_FALSE(rig.io.jog_owner().has_value());
  EXPECT_FALSE(rig.io.timer_deadline(1).has_value());
  EXPECT_EQ(rig.io.feedback_candidates(), 0);
}

}  // namespace
}  // namespace mcemu::iofunc::test
