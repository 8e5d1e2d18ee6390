// Jog functions 10 / 11 (iofunc.md §4.12): test IN-10/11. IN5 and IN6 need pins, so the standard
// rows run on MC632 (standard controller, IN1–IN8 and IN10); the last row on MCFLAT (RABBIT).
#include <gtest/gtest.h>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

TEST(Jog, In10In11OwnershipAndRelease) {
  Rig rig("MC632");
  run_rows(rig, {
                    {"W(3515.01,0x0A0A), .06 = 300, .07 = 1000, .09 = 500, .0A = 800; P(5,1), step(1)",
                     [](Rig& r) {
                       r.W(0x3515, 1, 0x0A0A);
                       r.W(0x3515, 6, 300);
                       r.W(0x3515, 7, 1000);
                       r.W(0x3515, 9, 500);
                       r.W(0x3515, 0x0A, 800);
                       r.P(5, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x6061), 3);
                       EXPECT_EQ(r.sw() & 0x6F, 0x27);
                       EXPECT_EQ(r.R(0x6083), 1000);
                       EXPECT_EQ(r.R(0x6073), 800);
                       EXPECT_EQ(r.R(0x60FF), 300);
                       EXPECT_EQ(r.io.jog_owner(), std::optional<int>(5));
                     }},
                    {"until(606Ch >= 295, 2 s); P(5,0), step(1)",
                     [](Rig& r) {
                       r.until([&] { return r.R(0x606C) >= 295; }, 2000);
                       r.P(5, false);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x6084), 500);
                       EXPECT_EQ(r.R(0x6083), 1000);
                       EXPECT_EQ(r.R(0x60FF), 0);
                       EXPECT_NE(r.sw() & 0x0020, 0);
                       EXPECT_FALSE(r.io.jog_owner().has_value());
                     }},
                    {"until(606Ch = 0, 2 s), step(500)",
                     [](Rig& r) {
                       r.until([&] { return r.R(0x606C) == 0; }, 2000);
                       r.step(500);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & 0x6F, 0x27);
                       EXPECT_EQ(r.R(0x6061), 3);
                     }},
                    {"W(3516.01,0x0B0B), 3516h.06 = -200; P(5,1); step(100); P(6,1), step(1)",
                     [](Rig& r) {
                       r.W(0x3516, 1, 0x0B0B);
                       r.W(0x3516, 6, -200);
                       r.P(5, true);
                       r.step(100);
                       EXPECT_EQ(r.R(0x60FF), 300);
                       r.P(6, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x60FF), -200);
                       EXPECT_EQ(r.io.jog_owner(), std::optional<int>(6));
                     }},
                    {"P(5,0), step(1)",
                     [](Rig& r) {
                       r.P(5, false);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x60FF), -200); }},
                    {"P(6,0), step(1)",
                     [](Rig& r) {
                       r.P(6, false);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x60FF), 0); }},
                });
}

TEST(Jog, RabbitModelDropsTheJog) {
  Rig rig("MCFLAT");
  rig.W(0x3515, 1, 0x0A0A);
  EXPECT_EQ(rig.R(0x3515, 1), 0x0A0A);
  rig.P(5, true);
  rig.step(10);
  EXPECT_EQ(rig.sw() & 0x6F, 0x40);
  EXPECT_EQ(rig.R(0x6060), 0);
  EXPECT_EQ(rig.R(0x60FF), 0);
  EXPECT_FALSE(rig.io.jog_owner().has_value());
  ASSERT_EQ(rig.diagnostics.size(), 1u);
  EXPECT_EQ(rig.diagnostics[0].level, core::DiagnosticLevel::warning);
}

// Writing the owner's .01 stops the jog; a mode change away from 3 ends ownership (§4.12).
TEST(Jog, OwnershipEndsOnCodeWriteAndModeChange) {
  Rig rig("MC632");
  rig.W(0x3515, 1, 0x000A);  // low byte form, jog +
  rig.W(0x3515, 6, 300);
  rig.P(5, true);
  rig.step();
  ASSERT_EQ(rig.R(0x60FF), 300);
  rig.W(0x3515, 1, 0x000A);
  EXPECT_EQ(rig.R(0x60FF), 0);
  EXPECT_FALSE(rig.io.jog_owner().has_value());

  rig.P(5, false);
  rig.step();
  rig.P(5, true);
  rig.step();
  ASSERT_EQ(rig.io.jog_owner(), std::optional<int>(5));
  rig.W(0x6060, 0, 1);
  rig.step();
  EXPECT_FALSE(rig.io.jog_owner().has_value());
  rig.W(0x60FF, 0, 123);
  rig.P(5, false);
  rig.step();
  EXPECT_EQ(rig.R(0x60FF), 123);  // no longer the owner: the release writes nothing
}

// A 10 or 11 in either byte makes a jog input whatever the other byte says (§4.2).
TEST(Jog, JogByteWinsOverTheOtherByte) {
  Rig rig("MC632");
  rig.W(0x3515, 1, 0x030B);  // jog − (low byte) with a counter in the high byte
  rig.W(0x3515, 6, 250);
  rig.P(5, true);
  rig.step();
  EXPECT_EQ(rig.R(0x60FF), -250);
  EXPECT_EQ(rig.R(0x3515, 3), 0);
  rig.P(5, false);
  rig.step();
  EXPECT_EQ(rig.R(0x60FF), 0);
}

// Function 5 clears jog ownership (§4.8).
TEST(Jog, QuickStopEndsOwnership) {
  Rig rig("MC632");
  rig.W(0x3515, 1, 0x0A0A);
  rig.W(0x3511, 1, 0x0500);
  rig.P(5, true);
  rig.step();
  ASSERT_TRUE(rig.io.jog_owner().has_value());
  rig.P(1, true);
  rig.step();
  EXPECT_FALSE(rig.io.jog_owner().has_value());
  EXPECT_EQ(rig.sw() & 0x6F, 0x07);
}

// Any motion function of another input takes the drive over and ends the jog (§4.12).
TEST(Jog, AnotherMotionFunctionEndsOwnership) {
  Rig rig("MC632");
  rig.W(0x3515, 1, 0x0A0A);
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 8, 5000);
  rig.P(5, true);
  rig.step();
  ASSERT_TRUE(rig.io.jog_owner().has_value());
  rig.P(1, true);
  rig.step();
  EXPECT_FALSE(rig.io.jog_owner().has_value());
  EXPECT_EQ(rig.R(0x6061), 1);
  EXPECT_EQ(rig.R(0x607A), 5000);
  rig.P(5, false);
  rig.step();
  EXPECT_EQ(rig.R(0x6061), 1);
}

}  // namespace
}  // namespace mcemu::iofunc::test
