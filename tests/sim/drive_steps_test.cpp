// sim::DriveSteps (sim/drive_steps.hpp) on a real drive: part order, what ends a quiet stretch, the
// deadlines of the I/O timers, fault durations and the RefGo jog timer hit the same step as with
// 1 ms stepping.
#include "sim/drive_steps.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "tests/support/device_fixture.hpp"

namespace mcemu::sim {
namespace {

// The drive bundle as the server builds it (tests/support/device_fixture.hpp): its DriveSteps with
// the bundle's parts (fault expiry, scope, RefGo programs, event hand-off, CANopen bus); a test's
// own parts run after them.
struct Rig {
  mcemu::testing::DeviceFixture fixture;
  od::ObjectDictionary& od = fixture.od();
  core::DriveCore& core = fixture.core();
  device::FaultInjections& faults = fixture.device().faults();
  refgo::Interpreter& refgo = fixture.refgo();
  DriveSteps& steps = fixture.device().steps();
  void W(std::uint16_t i, std::uint8_t s, std::int64_t v) {
    ASSERT_EQ(od.write(i, s, od::Value{v}, od::Origin::sdo), od::AbortCode::none) << std::hex << i;
    steps.touch();
  }
  std::int64_t R(std::uint16_t i, std::uint8_t s = 0) const { return *od.read_number(i, s); }
};

TEST(DriveSteps, PartsRunInOrderAfterTheDrive) {
  Rig r;
  std::vector<std::string> log;
  HookPart a([&] { log.push_back("a@" + std::to_string(r.core.time_ms())); });
  HookPart b([&] { log.push_back("b@" + std::to_string(r.core.time_ms())); });
  r.steps.add(a);
  r.steps.add(b);
  r.steps.step();
  EXPECT_EQ(log, (std::vector<std::string>{"a@1", "b@1"}));  // after the core's step 1
}

TEST(DriveSteps, IdleDriveIsQuietForeverAndEveryChangeEndsIt) {
  Rig r;
  EXPECT_EQ(r.steps.quiet_steps(), 0u);  // a new unit always steps first
  const Advanced a = r.steps.advance_to(600000);
  EXPECT_EQ(r.core.time_ms(), 600000u);
  EXPECT_LE(a.full, 3u);
  EXPECT_EQ(r.steps.quiet_steps(), k_forever);
  EXPECT_EQ(r.steps.next_deadline_ms(), k_forever);
  r.steps.touch();
  EXPECT_EQ(r.steps.quiet_steps(), 0u);
  r.steps.step();
  EXPECT_EQ(r.steps.quiet_steps(), k_forever);
  // an OD change nobody announced (no touch) still ends the quiet stretch
  ASSERT_EQ(r.od.write(0x6081, 0, od::Value{std::int64_t{777}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_EQ(r.steps.quiet_steps(), 0u);
}

TEST(DriveSteps, FaultDurationEndsInTheSameStepAsWithOneMillisecondSteps) {
  Rig r;
  r.steps.advance_to(100);
  ASSERT_TRUE(std::holds_alternative<nlohmann::json>(
      r.faults.create(R"({"kind": "drive.ambient", "celsius": 25, "durationMs": 5000})")));
  r.steps.touch();
  r.steps.step();
  EXPECT_EQ(r.steps.next_deadline_ms(), 5100u);
  r.steps.advance_to(5099);
  EXPECT_EQ(r.faults.active(), 1u);
  r.steps.advance_to(5100);
  EXPECT_EQ(r.faults.active(), 0u);
}

TEST(DriveSteps, JogTimerDeadline) {
  Rig r;
  r.steps.advance_to(10);
  r.refgo.programs().arm_jog(250);  // 60FFh := 0 at 260
  r.steps.touch();
  r.steps.step();
  EXPECT_EQ(r.steps.next_deadline_ms(), 260u);
  ASSERT_EQ(r.od.write(0x60FF, 0, od::Value{std::int64_t{5}}, od::Origin::internal), od::AbortCode::none);
  r.refgo.programs().arm_jog(250);  // a write from outside stopped it; re-armed at 11 → 261
  r.steps.touch();
  r.steps.advance_to(260);
  EXPECT_EQ(r.R(0x60FF), 5);
  r.steps.advance_to(261);
  EXPECT_EQ(r.R(0x60FF), 0);
}

// iofunc.md IN-4: a rising edge arms a 1 s timer; the move starts in the step after the delay.
TEST(DriveSteps, InputTimerFiresInTheSameStep) {
  Rig r;
  r.steps.advance_to(50);
  r.W(0x6067, 0, 10);
  r.W(0x3511, 1, 1024);
  r.W(0x3511, 5, 1000);
  r.W(0x3511, 8, 6300);
  r.W(0x3511, 6, 500);
  r.W(0x3511, 7, 400);
  r.W(0x3511, 9, 200);
  std::optional<std::uint64_t> started;
  HookPart watch([&] {
    if (!started && r.R(0x6061) == 1) started = r.core.time_ms();
  });
  r.steps.add(watch);
  ASSERT_TRUE(r.core.set_external_input_level(1, true));
  r.steps.touch();
  const std::uint64_t t0 = r.core.time_ms();
  // one call across the whole delay: the timer's step must not be skipped
  const Advanced a = r.steps.advance_to(t0 + 1001);
  EXPECT_LT(a.full, 10u);
  EXPECT_EQ(started, t0 + 1001);  // as with 1 ms steps (iofunc.md IN-4: mode 1 after step(1000), step(1))
  EXPECT_EQ(r.R(0x607A), 6300);
  EXPECT_EQ(r.R(0x6041) & 0x6F, 0x27);
  EXPECT_EQ(r.steps.quiet_steps(), 0u);  // enabled and moving: every step
}

}  // namespace
}  // namespace mcemu::sim
