// Motion input functions 4–7 (iofunc.md §4.3, §4.7–§4.9): tests IN-4, IN-4b, IN-4c, IN-5, IN-6
// and IN-7, row by row, plus the motion-start rules of §4.3.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

// IN-4's record: function 4 on the rising edge, 1 s delay, 6300 at 500/400/200.
void configure_in4(Rig& r) {
  r.W(0x6067, 0, 10);
  r.W(0x3511, 1, 1024);
  r.W(0x3511, 5, 1000);
  r.W(0x3511, 8, 6300);
  r.W(0x3511, 6, 500);
  r.W(0x3511, 7, 400);
  r.W(0x3511, 9, 200);
}

TEST(TimedMotionAbsolute, In4ManualExample) {
  Rig rig;
  std::uint64_t t0 = 0;
  run_rows(rig, {
                    {"t0: configure IN1, P(1,1)",
                     [&](Rig& r) {
                       configure_in4(r);
                       t0 = r.core.time_ms();
                       r.P(1, true);
                     },
                     nullptr},
                    {"step(1000)", [](Rig& r) { r.step(1000); },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x40);
                       EXPECT_EQ(r.R(0x6060), 0);
                       EXPECT_EQ(r.R(0x607A), 0);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                     }},
                    {"step(1)", [](Rig& r) { r.step(); },
                     [&](Rig& r) {
                       EXPECT_EQ(r.core.time_ms(), t0 + 1001);
                       EXPECT_EQ(r.R(0x6061), 1);
                       EXPECT_EQ(r.sw() & k_state_mask, 0x27);
                       EXPECT_EQ(r.R(0x6081), 500);
                       EXPECT_EQ(r.R(0x6083), 400);
                       EXPECT_EQ(r.R(0x6084), 200);
                       EXPECT_EQ(r.R(0x6073), 1000);
                       EXPECT_EQ(r.R(0x607A), 6300);
                       EXPECT_EQ(r.R(0x3511, 3), 6300);
                       EXPECT_EQ(r.R(0x3511, 4), 1);
                     }},
                    {"until(6041h bit 10, 10 s)", [](Rig& r) { r.until([&] { return r.reached(); }, 10000); },
                     [](Rig& r) { EXPECT_LE(std::llabs(r.R(0x6064) - 6300), 10); }},
                    {"P(1,0), step(2000)",
                     [](Rig& r) {
                       r.P(1, false);
                       r.step(2000);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3511, 4), 1);
                       EXPECT_EQ(r.R(0x607A), 6300);
                       EXPECT_EQ(r.sw() & k_state_mask, 0x27);
                       EXPECT_LE(std::llabs(r.R(0x6064) - 6300), 10);
                     }},
                });
}

TEST(TimedMotionAbsolute, In4bANewEdgeRestartsTheTimer) {
  Rig rig;
  configure_in4(rig);
  const std::uint64_t t0 = rig.core.time_ms();
  rig.P(1, true);
  rig.step(200);
  rig.P(1, false);
  rig.step(200);
  rig.P(1, true);
  rig.step(600);
  ASSERT_EQ(rig.core.time_ms(), t0 + 1000);
  EXPECT_EQ(rig.R(0x3511, 4), 0);
  EXPECT_EQ(rig.io.timer_deadline(1), std::optional<std::uint64_t>(t0 + 1400));
  rig.step(400);  // up to the step [t0+1399, t0+1400)
  EXPECT_EQ(rig.R(0x3511, 4), 0);
  rig.step();  // the step [t0+1400, t0+1401)
  EXPECT_EQ(rig.R(0x3511, 4), 1);
  EXPECT_EQ(rig.R(0x607A), 6300);
  EXPECT_FALSE(rig.io.timer_deadline(1).has_value());
}

TEST(TimedMotionAbsolute, In4cTargetInUserUnitsResultInIncrements) {
  Rig rig;
  rig.W(0x6092, 1, 360);
  rig.W(0x6091, 1, 5);
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 8, 90);
  rig.P(1, true);
  rig.step();
  EXPECT_EQ(rig.R(0x607A), 90);
  EXPECT_EQ(rig.R(0x3511, 3), 81920);
  EXPECT_EQ(rig.R(0x3511, 4), 1);
}

// §4.1: parameters ≤ 0 leave their target objects alone; .08 is always applied.
TEST(TimedMotionAbsolute, NonPositiveParametersLeaveTargetsUnchanged) {
  Rig rig;
  rig.W(0x6081, 0, 321);
  rig.W(0x6083, 0, 654);
  rig.W(0x6084, 0, 987);
  rig.W(0x6073, 0, 555);
  rig.W(0x3511, 1, 0x0400);
  for (std::uint8_t sub : {6, 9, 0x0A}) rig.W(0x3511, sub, 0);
  rig.W(0x3511, 7, 0);
  rig.W(0x3511, 9, -5);
  rig.W(0x3511, 8, 0);
  rig.W(0x607A, 0, 777);
  rig.P(1, true);
  rig.step();
  EXPECT_EQ(rig.R(0x6081), 321);
  EXPECT_EQ(rig.R(0x6083), 654);
  EXPECT_EQ(rig.R(0x6084), 987);
  EXPECT_EQ(rig.R(0x6073), 555);
  EXPECT_EQ(rig.R(0x607A), 0);
  EXPECT_EQ(rig.R(0x3511, 4), 1);
}

// §4.3: a drive in Fault is reset first; a cause that is still present drops the function.
TEST(MotionStart, FaultIsResetFirstAndAPresentCauseDropsTheFunction) {
  Rig rig;
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 8, 3000);
  rig.core.inject(core::FaultCause::sensor);
  rig.step();
  ASSERT_EQ(rig.sw() & 0x4F, 0x08);
  rig.P(1, true);
  rig.step();
  EXPECT_EQ(rig.sw() & 0x4F, 0x08);
  EXPECT_EQ(rig.R(0x3511, 4), 0);
  EXPECT_EQ(rig.R(0x607A), 0);
  EXPECT_FALSE(rig.diagnostics.empty());

  rig.core.clear(core::FaultCause::sensor);
  rig.P(1, false);
  rig.step();
  rig.P(1, true);
  rig.step();
  EXPECT_EQ(rig.sw() & k_state_mask, 0x27);
  EXPECT_EQ(rig.R(0x3511, 4), 1);
  EXPECT_EQ(rig.R(0x607A), 3000);
}

TEST(QuickStop, In5StopsAndCancelsDelayedMoves) {
  Rig rig;
  run_rows(rig, {
                    {"enable; velocity mode at 1000 until moving",
                     [](Rig& r) {
                       r.enable();
                       r.W(0x6060, 0, 3);
                       r.W(0x6083, 0, 1000);
                       r.W(0x60FF, 0, 1000);
                       r.until([&] { return r.R(0x606C) >= 990; }, 2000);
                     },
                     nullptr},
                    {"IN1 arms a move in 3 s; IN2 = quick stop; P(2,1), step(1)",
                     [](Rig& r) {
                       r.W(0x3511, 1, 0x0400);
                       r.W(0x3511, 5, 3000);
                       r.P(1, true);
                       r.W(0x3512, 1, 0x0500);
                       r.P(2, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x605A), 6);
                       EXPECT_EQ(r.sw() & k_state_mask, 0x07);
                       EXPECT_FALSE(r.io.timer_deadline(1).has_value());
                     }},
                    {"until(606Ch = 0, 5 s), step(4000)",
                     [](Rig& r) {
                       r.until([&] { return r.R(0x606C) == 0; }, 5000);
                       r.step(4000);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x07);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                       EXPECT_EQ(r.R(0x6060), 3);
                     }},
                    {"P(2,0), step(10)",
                     [](Rig& r) {
                       r.P(2, false);
                       r.step(10);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x07);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                     }},
                    {"a later motion function leaves Quick Stop Active (§4.3)",
                     [](Rig& r) {
                       r.W(0x3511, 5, 0);
                       r.W(0x3511, 8, 2000);
                       r.P(1, false);
                       r.step();
                       r.P(1, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x27);
                       EXPECT_EQ(r.R(0x6061), 1);
                       EXPECT_EQ(r.R(0x3511, 4), 1);
                     }},
                });
}

// §4.8: outside Operation Enabled only 605Ah changes.
TEST(QuickStop, OutsideOperationEnabledOnlyTheOptionChanges) {
  Rig rig;
  rig.W(0x6040, 0, 6);
  rig.W(0x3512, 1, 0x0500);
  rig.P(2, true);
  rig.step();
  EXPECT_EQ(rig.R(0x605A), 6);
  EXPECT_EQ(rig.sw() & k_state_mask, 0x21);
}

TEST(TimedMotionRelative, In6MovesRelativeToTheLastTarget) {
  Rig rig;
  run_rows(rig, {
                    {"configure IN1 = 0x0006",
                     [](Rig& r) {
                       r.W(0x60F2, 0, 0);
                       r.W(0x6067, 0, 10);
                       r.W(0x3511, 1, 0x0006);
                       r.W(0x3511, 5, 0);
                       r.W(0x3511, 8, 1000);
                       r.W(0x3511, 6, 500);
                       r.W(0x3511, 7, 1000);
                       r.W(0x3511, 9, 1000);
                     },
                     nullptr},
                    {"P(1,1), step(10)",
                     [](Rig& r) {
                       r.P(1, true);
                       r.step(10);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.sw() & k_state_mask, 0x40);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                     }},
                    {"P(1,0), step(1)",
                     [](Rig& r) {
                       r.P(1, false);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x6061), 1);
                       EXPECT_EQ(r.sw() & k_state_mask, 0x27);
                       EXPECT_EQ(r.R(0x3511, 3), 1000);
                       EXPECT_EQ(r.R(0x3511, 4), 1);
                     }},
                    {"wait for target reached; pulse IN1",
                     [](Rig& r) {
                       r.until([&] { return r.reached(); }, 10000);
                       r.pulse(1);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3511, 3), 2000);
                       EXPECT_EQ(r.R(0x3511, 4), 2);
                       r.until([&] { return r.reached(); }, 10000);
                       EXPECT_LE(std::llabs(r.R(0x6064) - 2000), 10);
                     }},
                    {"pulse IN1, and again 20 ms later while still moving",
                     [](Rig& r) {
                       r.pulse(1);
                       EXPECT_NE(r.sw() & 0x0100, 0) << "still moving";
                       r.pulse(1);
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3511, 3), 4000);
                       EXPECT_EQ(r.R(0x3511, 4), 4);
                       r.until([&] { return r.reached(); }, 10000);
                       EXPECT_LE(std::llabs(r.R(0x6064) - 4000), 10);
                     }},
                });
}

TEST(SetHome, In7HomesWithMethod35AndHonoursTheDelay) {
  Rig rig;
  std::uint64_t t = 0;
  run_rows(rig, {
                    {"enable, move to 4000; IN2 = 0x0700, method 35",
                     [](Rig& r) {
                       r.enable();
                       r.move_to(4000);
                       r.W(0x3512, 1, 0x0700);
                       r.W(0x3512, 5, 0);
                       r.W(0x3512, 6, 200);
                       r.W(0x3512, 7, 1000);
                       r.W(0x3512, 8, 0);
                       r.W(0x3512, 9, 35);
                       r.W(0x3512, 0x0A, 150);
                       r.W(0x6099, 1, 77);  // proves that .06 is written
                     },
                     nullptr},
                    {"P(2,1), step(1)",
                     [](Rig& r) {
                       r.P(2, true);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x6098), 35);
                       EXPECT_EQ(r.R(0x607C), 0);
                       EXPECT_EQ(r.R(0x6099, 1), 200);
                       EXPECT_EQ(r.R(0x609A), 1000);
                       EXPECT_EQ(r.R(0x6073), 150);
                       EXPECT_EQ(r.R(0x6060), 6);
                     }},
                    {"until(6041h bits 10 and 12, 1 s)",
                     [](Rig& r) { r.until([&] { return (r.sw() & 0x1400) == 0x1400; }, 1000); },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x6064), 0);
                       EXPECT_EQ(r.R(0x3512, 3), 0);
                       EXPECT_EQ(r.R(0x3512, 4), 0);
                     }},
                    {"repeat with .08 = 100 and .05 = 2000",
                     [&](Rig& r) {
                       r.W(0x3512, 8, 100);
                       r.W(0x3512, 5, 2000);
                       r.P(2, false);
                       r.step();
                       t = r.core.time_ms();
                       r.P(2, true);
                       r.step(2000);
                     },
                     [&](Rig& r) {
                       EXPECT_EQ(r.core.time_ms(), t + 2000);
                       EXPECT_EQ(r.R(0x6064), 0);
                       r.step();
                       EXPECT_EQ(r.R(0x6064), 100);
                       r.until([&] { return (r.sw() & 0x1400) == 0x1400; }, 1000);
                       EXPECT_EQ(r.R(0x6064), 100);
                     }},
                });
}

// §4.9: a homing method of 0 or outside −128…127 drops the function before anything is written.
TEST(SetHome, InvalidMethodIsDroppedWithAWarning) {
  for (std::int64_t method : {0LL, 128LL, -129LL}) {
    SCOPED_TRACE(method);
    Rig rig;
    rig.W(0x3512, 1, 0x0700);
    rig.W(0x3512, 9, method);
    rig.P(2, true);
    rig.step();
    EXPECT_EQ(rig.sw() & k_state_mask, 0x40);
    EXPECT_EQ(rig.R(0x6060), 0);
    ASSERT_EQ(rig.diagnostics.size(), 1u);
    EXPECT_EQ(rig.diagnostics[0].level, core::DiagnosticLevel::warning);
  }
}

}  // namespace
}  // namespace mcemu::iofunc::test
