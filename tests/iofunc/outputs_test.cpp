// Output functions on the running drive (iofunc.md §2.2, §5, §6): tests OUT-1 … OUT-6, OUT-4B,
// the 60FEh.01 ownership rules and IO-X on the combined pins of MCFLAT.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

int failures() { return ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count(); }

// Steps n times and checks after every step (stopping at the first new failure); returns how
// many steps the check returned true.
template <typename Check>
int watch(Rig& r, std::uint64_t n, Check check) {
  int high = 0;
  const int before = failures();
  for (std::uint64_t i = 0; i < n && failures() == before; ++i) {
    r.step();
    if (check()) ++high;
  }
  return high;
}

// A pulse of INn with the check after every one of its 20 steps.
template <typename Check>
int pulse_watching(Rig& r, int n, Check check) {
  r.P(n, true);
  int high = watch(r, 10, check);
  r.P(n, false);
  return high + watch(r, 10, check);
}

TEST(StatuswordMonitor, Out1FollowsTargetReachedThenTheFaultBit) {
  Rig rig;
  rig.W(0x3611, 1, 1);
  rig.W(0x3611, 2, 0x0400);
  rig.enable();
  const auto same = [&] {
    EXPECT_EQ(rig.out(1), (rig.sw() & 0x0400) != 0) << "6041h = " << rig.sw();
    return rig.out(1);
  };
  int high = watch(rig, 50, same);
  rig.start_move(3000);
  high += watch(rig, 1500, same);
  rig.start_move(0);
  high += watch(rig, 1500, same);
  EXPECT_GT(high, 100);
  EXPECT_LT(high, 3050);

  rig.W(0x3611, 2, 0x0008);
  rig.step();
  EXPECT_FALSE(rig.out(1));
  rig.core.inject(core::FaultCause::hw_sw_enable);
  rig.step();
  EXPECT_TRUE(rig.out(1));
}

// IN-9's first two rows: the refused switch-on raises FFF2h (1002h bit 9).
void raise_fff2(Rig& r) {
  r.W(0x3513, 1, 0x0900);
  r.W(0x6040, 0, 6);
  r.W(0x6040, 0, 7);
  ASSERT_EQ(r.R(0x603F), 0xFFF2);
}

TEST(StatusRegisterMonitor, Out2ShowsFff2) {
  Rig rig;
  rig.W(0x3612, 1, 2);
  rig.W(0x3612, 2, 0x0200);
  rig.step();
  EXPECT_FALSE(rig.out(2));
  raise_fff2(rig);
  EXPECT_FALSE(rig.out(2));  // evaluated at the next step
  rig.step();
  EXPECT_TRUE(rig.out(2));
  rig.W(0x6040, 0, 0x80);
  EXPECT_TRUE(rig.out(2));
  rig.step();
  EXPECT_FALSE(rig.out(2));
}

TEST(LimitMonitor, Out3Windows) {
  Rig rig;
  rig.W(0x3611, 1, 3);
  rig.W(0x3611, 2, 1);
  rig.W(0x3611, 3, 1000);
  rig.W(0x3611, 5, 100);
  rig.W(0x6081, 0, 40);
  rig.enable();
  const auto check = [&](auto in_window) {
    return [&rig, in_window] {
      const std::int64_t p = rig.R(0x6064);
      EXPECT_EQ(rig.out(1), in_window(p)) << "6064h = " << p;
      return rig.out(1);
    };
  };
  const auto right = [](std::int64_t p) { return 1000 <= p && p <= 1100; };
  const auto left = [](std::int64_t p) { return -1100 <= p && p <= -1000; };
  rig.start_move(2000);
  EXPECT_GE(watch(rig, 3000, check(right)), 2);
  ASSERT_TRUE(rig.reached());

  rig.W(0x3611, 2, 2);
  rig.W(0x3611, 4, -1000);
  rig.W(0x3611, 6, 100);
  rig.start_move(-2000);
  EXPECT_GE(watch(rig, 5000, check(left)), 2);
  ASSERT_TRUE(rig.reached());

  rig.W(0x3611, 2, 3);
  rig.start_move(2000);
  EXPECT_GE(watch(rig, 5000, check([&](std::int64_t p) { return left(p) || right(p); })), 4);

  rig.W(0x3611, 2, 0);
  rig.step();
  EXPECT_FALSE(rig.out(1));
}

void configure_positions(Rig& r) {
  r.W(0x6067, 0, 10);
  const std::int64_t targets[3] = {0, 4500, 9000};
  for (int n = 1; n <= 3; ++n) {
    const auto index = static_cast<std::uint16_t>(0x3510 + n);
    r.W(index, 1, 0x0400);
    r.W(index, 8, targets[n - 1]);
    r.W(index, 5, 0);
  }
}

TEST(PositionReached, Out4PerInputAndGeneral) {
  Rig rig;
  configure_positions(rig);
  rig.W(0x3611, 1, 4);
  rig.W(0x3611, 2, 2);
  rig.W(0x3611, 5, 20);
  rig.W(0x3611, 6, 20);
  rig.step();
  EXPECT_TRUE(rig.out(1)) << "IN2 has not moved: result 0 is held at 0";

  const auto near = [&](std::int64_t lo, std::int64_t hi) {
    return [&rig, lo, hi] {
      const std::int64_t d = rig.R(0x6063) - 4500;
      EXPECT_EQ(rig.out(1), lo <= d && d <= hi) << "6063h = " << rig.R(0x6063);
      return rig.out(1);
    };
  };
  pulse_watching(rig, 2, near(-20, 20));
  EXPECT_GT(watch(rig, 1000, near(-20, 20)), 100);
  ASSERT_TRUE(rig.out(1));

  pulse_watching(rig, 3, near(-20, 20));
  watch(rig, 1000, near(-20, 20));
  EXPECT_FALSE(rig.out(1));

  rig.W(0x3611, 5, 50);
  rig.W(0x3611, 6, 0);
  pulse_watching(rig, 2, near(0, 50));
  watch(rig, 1000, near(0, 50));
  EXPECT_TRUE(rig.out(1));

  rig.W(0x60F2, 0, 0);
  rig.W(0x3611, 2, 0);
  rig.W(0x3611, 5, 20);
  rig.W(0x3611, 6, 20);
  rig.start_move(-3000);
  const int held = watch(rig, 2000, [&] {
    const std::int64_t d = rig.R(0x6063) - (-3000);
    EXPECT_EQ(rig.out(1), -20 <= d && d <= 20) << "6063h = " << rig.R(0x6063);
    return rig.out(1);
  });
  EXPECT_GT(held, 100);
}

std::pair<bool, bool> feedback(const Rig& r) { return {r.out(1), r.out(2)}; }

TEST(PositionReached, Out4BBitCodedFeedback) {
  Rig rig;
  using P = std::pair<bool, bool>;
  run_rows(rig, {
                    {"IN1..IN3 = positions; OUT1/OUT2 f = 4, c = 255, windows 20; drive at 0",
                     [](Rig& r) {
                       configure_positions(r);
                       for (std::uint16_t o : {0x3611, 0x3612}) {
                         r.W(o, 1, 4);
                         r.W(o, 2, 255);
                         r.W(o, 5, 20);
                         r.W(o, 6, 20);
                       }
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(feedback(r), P(true, false)); }},
                    {"pulse IN2; during the move",
                     [](Rig& r) {
                       int moving_steps = 0;
                       pulse_watching(r, 2, [&] {
                         const std::int64_t p = r.R(0x6063);
                         if (std::llabs(p) > 20 && std::llabs(p - 4500) > 20) {
                           ++moving_steps;
                           EXPECT_EQ(feedback(r), P(false, false)) << "6063h = " << p;
                         }
                         return false;
                       });
                       EXPECT_GT(moving_steps, 5);
                     },
                     nullptr},
                    {"target 4500 held", [](Rig& r) { r.until([&] { return r.reached(); }, 5000); },
                     [](Rig& r) { EXPECT_EQ(feedback(r), P(false, true)); }},
                    {"pulse IN3; target 9000 held",
                     [](Rig& r) {
                       r.pulse(3);
                       r.until([&] { return r.reached(); }, 5000);
                     },
                     [](Rig& r) { EXPECT_EQ(feedback(r), P(true, true)); }},
                    {"pulse IN1; target 0 held",
                     [](Rig& r) {
                       r.pulse(1);
                       r.until([&] { return r.reached(); }, 5000);
                     },
                     [](Rig& r) { EXPECT_EQ(feedback(r), P(true, false)); }},
                    {"OUT1/OUT2 f = 6; FFF2h while at 0",
                     [](Rig& r) {
                       r.W(0x3611, 1, 6);
                       r.W(0x3612, 1, 6);
                       r.step();
                       EXPECT_EQ(feedback(r), P(true, false));
                       r.core.inject(core::FaultCause::hw_sw_enable);
                       r.step();
                     },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x603F), 0xFFF2);
                       EXPECT_EQ(feedback(r), P(false, false));
                     }},
                });
}

TEST(DriveOk, Out5) {
  Rig rig;
  rig.W(0x3611, 1, 5);
  rig.step();
  EXPECT_TRUE(rig.out(1));
  raise_fff2(rig);
  rig.step();
  EXPECT_FALSE(rig.out(1));
  rig.W(0x6040, 0, 0x80);
  rig.step();
  EXPECT_TRUE(rig.out(1));
  rig.core.inject(core::FaultCause::sensor_warning);
  rig.step();
  ASSERT_NE(rig.sw() & 0x0080, 0);
  EXPECT_FALSE(rig.out(1));
  rig.core.clear(core::FaultCause::sensor_warning);
  rig.step();
  EXPECT_TRUE(rig.out(1));
}

TEST(ReachedAndOk, Out6) {
  Rig rig;
  rig.W(0x3611, 1, 6);
  rig.W(0x3611, 2, 1);
  rig.W(0x3611, 5, 20);
  rig.W(0x3611, 6, 20);
  rig.W(0x3511, 1, 0x0400);
  rig.W(0x3511, 8, 4500);
  rig.pulse(1);
  rig.until([&] { return rig.reached(); }, 5000);
  EXPECT_TRUE(rig.out(1));
  rig.core.inject(core::FaultCause::hw_sw_enable);
  rig.step();
  EXPECT_LE(std::llabs(rig.R(0x6063) - 4500), 20);
  EXPECT_FALSE(rig.out(1));
}

// §2.2: manual latch, ownership, composition and function switching.
TEST(OutputWord, ManualWritesOwnershipAndSwitching) {
  Rig rig;
  rig.W(0x60FE, 1, 65536);
  EXPECT_EQ(rig.outputs(), 0x10000u);
  rig.W(0x60FE, 1, 393216);
  EXPECT_EQ(rig.outputs(), 0x60000u);
  rig.W(0x60FE, 1, 0x0000FFFF | 0x10000);  // bits outside 16…19 are ignored
  EXPECT_EQ(rig.outputs(), 0x10000u);

  rig.W(0x3612, 1, 5);  // OUT2 owned by "drive OK"
  EXPECT_FALSE(rig.out(2)) << "a new function shows its level from the next step";
  rig.step();
  EXPECT_TRUE(rig.out(2));
  rig.W(0x60FE, 1, 0);  // accepted; the owned bit stays
  EXPECT_EQ(rig.outputs(), 0x20000u);
  rig.W(0x60FE, 1, 0x90000);  // OUT1 and OUT4 manual high
  EXPECT_EQ(rig.outputs(), 0xB0000u);
  rig.step(3);
  EXPECT_EQ(rig.outputs(), 0xB0000u);

  rig.W(0x3614, 1, 1);  // OUT4 owned by a statusword mask of 0: low from the next step
  EXPECT_TRUE(rig.out(4));
  rig.step();
  EXPECT_FALSE(rig.out(4));
  rig.W(0x3614, 1, 0);  // back to manual: the latch was cleared
  EXPECT_FALSE(rig.out(4));

  rig.W(0x3612, 1, 0);  // non-zero → 0: the output goes low at once
  EXPECT_FALSE(rig.out(2));
  EXPECT_TRUE(rig.out(1));

  rig.W(0x60FE, 2, 0xFFFFFFFF);  // bit mask and selector: stored, no effect
  rig.W(0x60FE, 3, 0xFFFFFFFF);
  rig.W(0x60FE, 1, 0x40000);
  EXPECT_EQ(rig.outputs(), 0x40000u);
  EXPECT_EQ(rig.R(0x60FE, 2), 0xFFFFFFFF);
}

// Writes that try to change an owned output succeed, change nothing and leave a debug note.
TEST(OutputWord, OwnedWriteIsNotedAtDebugLevel) {
  Rig rig;
  rig.W(0x3611, 1, 5);
  rig.step();
  rig.diagnostics.clear();
  rig.W(0x60FE, 1, 0x10000);  // the owned bit already has this level: nothing to note
  EXPECT_TRUE(rig.io.drain_diagnostics().empty());
  rig.W(0x60FE, 1, 0);
  const auto notes = rig.io.drain_diagnostics();
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].level, core::DiagnosticLevel::debug);
  EXPECT_TRUE(rig.out(1));
}

// §5.4 on the running drive: in rotary operation (60F2h bits 6–7) the distance to the reference is
// reduced by one revolution of the rotary range first.
TEST(PositionReached, RotaryOperationReducesByTheRange) {
  Rig rig;
  rig.W(0x3611, 1, 4);
  rig.W(0x3611, 2, 2);
  rig.W(0x3611, 5, 20);
  rig.W(0x3611, 6, 20);
  rig.W(0x3511, 1, 0x0600);  // IN1: relative move of one revolution and 100
  rig.W(0x3511, 8, 65636);
  rig.pulse(1);
  rig.until([&] { return rig.reached(); }, 10000);
  ASSERT_NEAR(static_cast<double>(rig.R(0x6063)), 65636, 10);
  rig.W(0x3512, 3, 100);  // IN2's result register, written directly
  rig.step();
  EXPECT_FALSE(rig.out(1)) << "linear operation: 65536 increments away";
  rig.W(0x60F2, 0, 0xC0);
  rig.step();
  EXPECT_TRUE(rig.out(1)) << "rotary operation: the same position one revolution on";
  rig.W(0x3512, 3, 100 + 32768);
  rig.step();
  EXPECT_FALSE(rig.out(1));
}

// RefGo SO/CO are read-modify-writes of 60FEh.01 (refgo.md §7.8).
void so(Rig& r, int n) { r.W(0x60FE, 1, r.R(0x60FE, 1) | (std::int64_t{1} << (15 + n))); }
void co(Rig& r, int n) { r.W(0x60FE, 1, r.R(0x60FE, 1) & ~(std::int64_t{1} << (15 + n))); }

TEST(CombinedPins, IoX) {
  Rig flat("MCFLAT");
  run_rows(flat, {
                     {"W(3511.01,0x0303); W(60FE.01,0x10000)",
                      [](Rig& r) {
                        r.W(0x3511, 1, 0x0303);
                        r.W(0x60FE, 1, 0x10000);
                      },
                      [](Rig& r) {
                        EXPECT_EQ(r.inputs() & 0x10000, 0x10000u);
                        r.step();
                        EXPECT_EQ(r.R(0x3511, 3), 1);
                      }},
                     {"W(60FE.01,0), step(1)",
                      [](Rig& r) {
                        r.W(0x60FE, 1, 0);
                        r.step();
                      },
                      [](Rig& r) {
                        EXPECT_EQ(r.inputs() & 0x10000, 0u);
                        EXPECT_EQ(r.R(0x3511, 3), 2);
                      }},
                     {"W(3612.01,5), step(1)",
                      [](Rig& r) {
                        r.W(0x3612, 1, 5);
                        r.step();
                      },
                      [](Rig& r) {
                        EXPECT_TRUE(r.out(2));
                        EXPECT_EQ(r.inputs() & 0x20000, 0x20000u);
                      }},
                     {"W(60FE.01,0); CO2",
                      [](Rig& r) {
                        r.W(0x60FE, 1, 0);
                        co(r, 2);
                      },
                      [](Rig& r) { EXPECT_TRUE(r.out(2)); }},
                     {"W(3612.01,0), step(1)",
                      [](Rig& r) {
                        r.W(0x3612, 1, 0);
                        r.step();
                      },
                      [](Rig& r) {
                        EXPECT_FALSE(r.out(2));
                        EXPECT_EQ(r.inputs() & 0x20000, 0u);
                      }},
                     {"SO2", [](Rig& r) { so(r, 2); },
                      [](Rig& r) {
                        EXPECT_TRUE(r.out(2));
                        EXPECT_EQ(r.inputs() & 0x20000, 0x20000u);
                      }},
                 });

  Rig f349;
  f349.W(0x3511, 1, 0x0303);
  f349.W(0x60FE, 1, 0x10000);
  EXPECT_EQ(f349.inputs(), 0u);
  f349.step();
  f349.W(0x60FE, 1, 0);
  f349.step();
  EXPECT_EQ(f349.inputs(), 0u);
  EXPECT_EQ(f349.R(0x3511, 3), 0);
}

// An output function feeding its own IO pin: the input function reacts one step later (§6 rule 2).
TEST(CombinedPins, LoopAdvancesOneEdgePerStep) {
  Rig rig("MCFLAT");
  rig.W(0x3512, 1, 0x0300);
  rig.W(0x3612, 1, 5);
  rig.step();
  EXPECT_TRUE(rig.out(2));
  EXPECT_EQ(rig.inputs() & 0x20000, 0x20000u);
  EXPECT_EQ(rig.R(0x3512, 3), 0);
  rig.step();
  EXPECT_EQ(rig.R(0x3512, 3), 1);
}

// The outputs an output function owns are cached by the settings generation: a function that
// arrives by a bulk load (a restore) takes the output in the next step like a written one, and a
// manual level no longer reaches an owned output.
TEST(OutputOwnership, FunctionLoadedInBulkTakesTheOutput) {
  Rig rig;
  rig.enable();
  rig.step();
  ASSERT_NE(rig.sw() & 0x0004, 0) << "operation enabled";
  EXPECT_FALSE(rig.out(1)) << "manual, low";
  const std::array<od::StoredValue, 2> load{od::StoredValue{0x3611, 1, std::int64_t{1}},
                                            od::StoredValue{0x3611, 2, std::int64_t{0x0004}}};
  ASSERT_TRUE(rig.od.load_values(load).empty());
  rig.step();
  EXPECT_TRUE(rig.out(1)) << "statusword monitor on bit 2 (operation enabled)";
  rig.W(0x3611, 2, 0x0040);  // switch on disabled: low while enabled
  rig.step();
  EXPECT_FALSE(rig.out(1));
  rig.W(0x60FE, 1, 1 << 16);  // a manual level does not reach an owned output
  rig.step();
  EXPECT_FALSE(rig.out(1));
}

}  // namespace
}  // namespace mcemu::iofunc::test
