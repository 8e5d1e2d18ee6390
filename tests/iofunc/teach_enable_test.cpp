// Level functions 8 and 9 (iofunc.md §4.10, §4.11): tests IN-8 and IN-9 (the latter as a table
// over the high-active and low-active codes, also with a second function in the other byte).
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

TEST(Teach, In8TeachesInsteadOfMoving) {
  Rig rig;
  std::int64_t here = 0;
  run_rows(rig, {
                    {"IN1/IN2 = 0x0400 (0 / 4500), IN4 = 0x0008; move to 2000",
                     [](Rig& r) {
                       r.W(0x3511, 1, 0x0400);
                       r.W(0x3511, 8, 0);
                       r.W(0x3512, 1, 0x0400);
                       r.W(0x3512, 8, 4500);
                       r.W(0x3514, 1, 0x0008);
                       r.W(0x6067, 0, 10);
                       r.enable();
                       r.move_to(2000);
                     },
                     nullptr},
                    {"P(4,1), P(2,1), step(1)",
                     [&](Rig& r) {
                       here = r.R(0x6064);
                       r.P(4, true);
                       r.P(2, true);
                       r.step();
                     },
                     [&](Rig& r) {
                       EXPECT_TRUE(r.io.teach_active());
                       EXPECT_LE(std::llabs(here - 2000), 10);
                       EXPECT_EQ(r.R(0x3512, 8), here);
                       EXPECT_EQ(r.R(0x607A), 2000);
                       EXPECT_EQ(r.R(0x6061), 1);
                       EXPECT_EQ(r.R(0x3512, 3), 0);
                       EXPECT_EQ(r.R(0x3512, 4), 0);
                       EXPECT_FALSE(r.io.timer_deadline(2).has_value());
                     }},
                    {"step(2000)", [](Rig& r) { r.step(2000); },
                     [](Rig& r) { EXPECT_LE(std::llabs(r.R(0x6064) - 2000), 10); }},
                    {"P(2,0), P(4,0), step(1), P(2,1), step(1)",
                     [](Rig& r) {
                       r.P(2, false);
                       r.P(4, false);
                       r.step();
                       r.P(2, true);
                       r.step();
                     },
                     [&](Rig& r) {
                       EXPECT_FALSE(r.io.teach_active());
                       EXPECT_EQ(r.R(0x607A), here);
                       EXPECT_EQ(r.R(0x3512, 3), here);
                       EXPECT_EQ(r.R(0x3512, 4), 1);
                     }},
                    {"W(3510.02,0x0108), step(1)",
                     [&](Rig& r) {
                       here = r.R(0x6064);
                       r.W(0x3510, 2, 0x0108);
                       r.step();
                     },
                     [&](Rig& r) { EXPECT_EQ(r.R(0x3511, 8), here); }},
                });
}

// Teach does not affect function 6 (§4.10), and the high-byte form 0x0800 is active-high too.
TEST(Teach, RelativeMovesAreNotTaught) {
  Rig rig;
  rig.W(0x3511, 1, 0x0600);
  rig.W(0x3511, 8, 1000);
  rig.W(0x3514, 1, 0x0800);
  rig.P(4, true);
  rig.step();
  rig.P(1, true);
  rig.step();
  EXPECT_EQ(rig.R(0x3511, 8), 1000);
  EXPECT_EQ(rig.R(0x3511, 4), 1);
  EXPECT_EQ(rig.R(0x3511, 3), 1000);
}

// Teach applies to a 3510h.02 command with ZZ = 4 (§4.13).
TEST(Teach, CommandWithFunction4IsTaught) {
  Rig rig;
  rig.W(0x3512, 8, 4500);
  rig.W(0x3514, 1, 0x0008);
  rig.P(4, true);
  rig.step();
  rig.W(0x3510, 2, 0x0204);
  rig.step();
  EXPECT_EQ(rig.R(0x3512, 8), rig.R(0x6064));
  EXPECT_EQ(rig.R(0x3512, 4), 0);
  EXPECT_EQ(rig.sw() & k_state_mask, 0x40);
}

struct EnableCase {
  const char* name;
  std::int64_t code;  // 3513h.01
  bool active_high;   // level of IN3 that enables
};

class SoftwareEnable : public ::testing::TestWithParam<EnableCase> {};

TEST_P(SoftwareEnable, In9) {
  const EnableCase c = GetParam();
  const bool on = c.active_high;
  const bool off = !c.active_high;
  Rig rig;
  run_rows(rig, {
                    {"IN3 at the disabling level; W(3513.01); W(6040,6)",
                     [&](Rig& r) {
                       r.P(3, off);
                       r.step();
                       r.W(0x3513, 1, c.code);
                       r.W(0x6040, 0, 6);
                     },
                     [](Rig& r) { EXPECT_EQ(r.sw() & k_state_mask, 0x21); }},
                    {"W(6040,7)", [](Rig& r) { r.W(0x6040, 0, 7); },
                     [](Rig& r) {
                       EXPECT_NE(r.sw() & 0x0008, 0);
                       EXPECT_EQ(r.R(0x603F), 0xFFF2);
                       EXPECT_NE(r.R(0x1002) & 0x200, 0);
                       EXPECT_EQ(r.R(0x1003, 1), 0xFFF2);
                     }},
                    {"W(6040,0x80)", [](Rig& r) { r.W(0x6040, 0, 0x80); },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x40);
                       EXPECT_EQ(r.R(0x1002) & 0x200, 0);
                     }},
                    {"IN3 enabling; 6, 7, 15",
                     [&](Rig& r) {
                       r.P(3, on);
                       r.W(0x6040, 0, 6);
                       r.W(0x6040, 0, 7);
                       r.W(0x6040, 0, 15);
                     },
                     [](Rig& r) { EXPECT_EQ(r.sw() & k_state_mask, 0x27); }},
                    {"velocity mode 500, moving; IN3 disabling",
                     [&](Rig& r) {
                       r.W(0x6060, 0, 3);
                       r.W(0x60FF, 0, 500);
                       r.until([&] { return r.R(0x606C) >= 400; }, 2000);
                       r.P(3, off);
                       r.step();
                     },
                     [](Rig& r) {
                       // 605Ch = 1: the drive stays Operation Enabled while it ramps down
                       EXPECT_EQ(r.sw() & k_state_mask, 0x27);
                       EXPECT_GT(r.R(0x606C), 0);
                       r.until([&] { return (r.sw() & 0x4F) == 0x40; }, 2000);
                       EXPECT_EQ(r.sw() & 0x0008, 0);
                       EXPECT_EQ(r.R(0x1002) & 0x200, 0);
                       EXPECT_EQ(r.R(0x6060), 3);
                     }},
                    {"W(3511.01,0x0400), P(1,1), step(1)",
                     [](Rig& r) {
                       r.W(0x3511, 1, 0x0400);
                       r.W(0x3511, 8, 5000);
                       r.P(1, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & 0x4F, 0x08);
                       EXPECT_EQ(r.R(0x603F), 0xFFF2);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                       EXPECT_EQ(r.R(0x607A), 0);
                     }},
                });
}

INSTANTIATE_TEST_SUITE_P(Codes, SoftwareEnable,
                         ::testing::Values(EnableCase{"high_active_0900", 0x0900, true},
                                           EnableCase{"low_active_0009", 0x0009, false},
                                           EnableCase{"high_byte_9_with_capture_0901", 0x0901, true},
                                           EnableCase{"low_byte_9_with_capture_0109", 0x0109, false}),
                         [](const auto& p) { return std::string(p.param.name); });

// Several function-9 inputs: all conditions must hold (§4.11).
TEST(SoftwareEnableAnd, AllInputsMustAgree) {
  Rig rig;
  rig.W(0x3513, 1, 0x0900);
  rig.W(0x3514, 1, 0x0009);
  rig.P(3, true);
  rig.P(4, true);
  rig.step();
  EXPECT_FALSE(rig.core.software_enabled());
  rig.P(4, false);
  rig.step();
  EXPECT_TRUE(rig.core.software_enabled());
  rig.enable();
  EXPECT_EQ(rig.sw() & k_state_mask, 0x27);
}

// Losing the enable cancels pending timers and the jog (§4.11, §6 rule 5).
TEST(SoftwareEnableLoss, CancelsTimers) {
  Rig rig;
  rig.W(0x3513, 1, 0x0900);
  rig.P(3, true);
  rig.step();
  rig.enable();
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 5, 3000);
  rig.W(0x3511, 8, 3000);
  rig.P(1, true);
  rig.step();
  ASSERT_TRUE(rig.io.timer_deadline(1).has_value());
  rig.P(3, false);
  rig.step();
  EXPECT_FALSE(rig.io.timer_deadline(1).has_value());
  rig.P(3, true);
  rig.step(3500);
  EXPECT_EQ(rig.R(0x3511, 4), 0);
  EXPECT_EQ(rig.sw() & k_state_mask, 0x40);
}

}  // namespace
}  // namespace mcemu::iofunc::test
