// The CiA 402 rules against the real drive core (MC349): the harness feeds the lint the way a
// bundle would (each write with 6041h/6061h read after it, core events after each write and step,
// PowerOn after power_on()), so the rules are checked against what the core really shows — a
// careful master gets no finding, a sloppy one exactly the expected ones.
#include <gtest/gtest.h>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

struct Bench {
  model::ModelPreset preset = *model::find_preset("MC349");
  od::ObjectDictionary od{preset};
  core::DriveCore core{preset, od};
  Lint lint;

  Bench() {
    core.power_on();
    lint.engine.observe(PowerOn{core.time_ms(), sw(), static_cast<std::uint16_t>(od.number(0x6040, 0)),
                                static_cast<std::int8_t>(od.number(0x6060, 0)), od.number(0x60FF, 0)});
    step();
  }

  std::uint16_t sw() const { return static_cast<std::uint16_t>(od.number(0x6041, 0)); }

  void drain() {
    for (const auto& e : core.drain_events()) lint.engine.observe(CoreEvent{core.time_ms(), e});
  }
  od::AbortCode write(std::uint16_t index, std::int64_t value, od::Origin origin = od::Origin::sdo) {
    const auto r = od.write(index, 0, od::Value{value}, origin);
    OdWrite w;
    w.time = core.time_ms();
    w.conn = 1;
    w.origin = origin;
    w.index = index;
    w.value = value;
    w.result = r;
    w.statusword_after = sw();
    w.mode_after = static_cast<std::int8_t>(od.number(0x6061, 0));
    lint.engine.observe(w);
    drain();
    return r;
  }
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) {
      core.step();
      drain();
    }
  }
  template <typename Pred>
  bool step_until(Pred p, int max_ms) {
    for (int i = 0; i < max_ms; ++i) {
      if (p()) return true;
      step();
    }
    return p();
  }
};

TEST(RealCore, CarefulProfilePositionMasterIsQuiet) {
  Bench b;
  ASSERT_EQ(b.write(0x6060, 1), od::AbortCode::none);
  b.step();
  b.write(0x6040, 0x06);
  b.write(0x6040, 0x07);
  b.write(0x6040, 0x0F);
  ASSERT_EQ(b.sw() & 0x6F, 0x27);
  b.write(0x6081, 1000);
  for (std::int64_t target : {20000, 0, 40000}) {
    b.write(0x607A, target);
    b.write(0x6040, 0x1F);
    ASSERT_TRUE(b.step_until([&] { return (b.sw() & 0x1000) != 0; }, 10));  // acknowledged
    b.write(0x6040, 0x0F);
    ASSERT_TRUE(b.step_until([&] { return (b.sw() & 0x1400) == 0x0400; }, 5000));  // reached, released
  }
  b.write(0x6040, 0x07);  // disable operation (ramp)
  b.step(50);
  b.write(0x6040, 0x06);
  b.write(0x6040, 0x00);
  EXPECT_TRUE(b.lint.found.empty()) << finding_text(b.lint.found.front());
}

TEST(RealCore, CarefulProfileVelocityMasterIsQuiet) {
  Bench b;
  b.write(0x6060, 3);
  b.step();
  b.write(0x60FF, 0);
  b.write(0x6040, 0x06);
  b.write(0x6040, 0x0F);  // 3+4
  b.write(0x60FF, 500);
  b.step(300);
  b.write(0x60FF, 0);
  ASSERT_TRUE(b.step_until([&] { return (b.sw() & 0x0100) == 0; }, 5000));
  b.write(0x6060, 1);  // at standstill
  b.write(0x6040, 0x06);
  EXPECT_TRUE(b.lint.found.empty()) << finding_text(b.lint.found.front());
}

TEST(RealCore, SloppyMasterGetsExactlyTheExpectedFindings) {
  Bench b;
  b.write(0x6060, 3);
  b.step();
  b.write(0x6040, 0x0F);  // skips Shutdown: ignored
  EXPECT_EQ(b.sw() & 0x4F, 0x40);
  b.write(0x6040, 0x06);
  b.write(0x60FF, 300);
  b.write(0x6040, 0x0F);  // enables PV with a target: the axis runs at once
  b.step(200);
  ASSERT_TRUE(b.sw() & 0x0100);
  b.write(0x6060, 1);  // mode change while moving
  b.step(2000);
  ASSERT_EQ(b.lint.found.size(), 3U);
  EXPECT_EQ(b.lint.found[0].rule, RuleId::cia402_command_ignored);
  EXPECT_EQ(b.lint.found[1].rule, RuleId::cia402_enable_with_velocity_target);
  EXPECT_EQ(b.lint.found[2].rule, RuleId::cia402_mode_change_while_moving);
}

TEST(RealCore, SetpointsFasterThanTheBufferDrainsAreReported) {
  // A set of set-points (bit 5 = 0) sent without waiting for 6041h bit 12 to drop: once the
  // buffer is full, bit 12 stays set and the core rejects the next edge (drive-core.md §7.2).
  Bench b;
  b.write(0x6060, 1);
  b.step();
  b.write(0x6040, 0x06);
  b.write(0x6040, 0x0F);
  b.write(0x6081, 10);  // slow: the buffer fills
  int rejected_before = 0;
  for (int k = 1; k <= 30; ++k) {
    b.write(0x607A, 100000 * k);
    b.write(0x6040, 0x1F);
    b.write(0x6040, 0x0F);
    if (b.lint.found.empty()) ++rejected_before;
  }
  ASSERT_FALSE(b.lint.found.empty());
  EXPECT_TRUE(b.lint.only(RuleId::cia402_setpoint_before_ack));
  EXPECT_GE(rejected_before, 20);  // the buffer of 20 (drive-core.md §7.2) took the first ones
}

TEST(RealCore, FaultResetHeldAndMotionInFault) {
  Bench b;
  b.write(0x6060, 1);
  b.step();
  b.write(0x6040, 0x06);
  b.write(0x6040, 0x0F);
  b.core.inject(core::FaultCause::over_temperature);
  b.step(5);
  ASSERT_EQ(b.sw() & 0x4F, 0x08);
  b.write(0x6040, 0x1F);  // motion in fault
  b.core.clear(core::FaultCause::over_temperature);
  b.step(5);
  b.write(0x6040, 0x80);  // reset edge
  b.write(0x6040, 0x86);  // bit 7 held: Shutdown ignored
  EXPECT_EQ(b.sw() & 0x4F, 0x40);
  ASSERT_EQ(b.lint.found.size(), 2U);
  EXPECT_EQ(b.lint.found[0].rule, RuleId::cia402_motion_in_fault);
  EXPECT_EQ(b.lint.found[1].rule, RuleId::cia402_fault_reset_held);
}

}  // namespace
}  // namespace mcemu::lint::test
