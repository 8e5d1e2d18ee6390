// CiA 402 state machine (drive-core.md §4, §5, §15 items 1–3): every command of §4.2 in every
// state, with every option code, checked right after the write and after the ramp.
#include <gtest/gtest.h>

#include <sstream>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using S = PdsState;

constexpr std::uint16_t base_of(S s) {
  switch (s) {
    case S::not_ready_to_switch_on: return 0x0000;
    case S::switch_on_disabled: return 0x0040;
    case S::ready_to_switch_on: return 0x0021;
    case S::switched_on: return 0x0023;
    case S::operation_enabled: return 0x0027;
    case S::quick_stop_active: return 0x0007;
    case S::fault_reaction_active: return 0x000F;
    case S::fault: return 0x0008;
  }
  return 0;
}

struct Case {
  S from;
  std::uint16_t cw;
  int qs_option;    // 605Ah
  int stop_option;  // 605Bh and 605Ch
  S after_write;
  S after_ramp;
};

std::string name_of(const Case& c) {
  std::ostringstream o;
  o << to_string(c.from) << "_cw" << std::hex << c.cw << std::dec << "_qs" << c.qs_option << "_opt" << c.stop_option;
  return o.str();
}

// The expected result, read off the tables of §4.2, §4.3 and §4.5.
Case expect(S from, std::uint16_t cw, int qs, int opt) {
  const bool dv = cw == 0x00 || cw == 0x04;
  const bool q = cw == 0x02 || cw == 0x0B;
  const bool shut = cw == 0x06 || cw == 0x0E;
  const bool on = cw == 0x07;
  const bool en = cw == 0x0F;
  const bool reset = (cw & 0x80) != 0;
  S now = from;
  S later = from;
  switch (from) {
    case S::switch_on_disabled:
      if (shut) now = later = S::ready_to_switch_on;
      break;
    case S::ready_to_switch_on:
      if (on) now = later = S::switched_on;
      if (en) now = later = S::operation_enabled;
      if (dv || q) now = later = S::switch_on_disabled;
      break;
    case S::switched_on:
      if (en) now = later = S::operation_enabled;
      if (shut) now = later = S::ready_to_switch_on;
      if (dv || q) now = later = S::switch_on_disabled;
      break;
    case S::operation_enabled:
      if (dv) now = later = S::switch_on_disabled;
      if (q) {
        now = qs == 0 ? S::switch_on_disabled : S::quick_stop_active;
        later = (qs == 5 || qs == 6) ? S::quick_stop_active : S::switch_on_disabled;
      }
      if (shut) {
        now = opt == 0 ? S::ready_to_switch_on : S::operation_enabled;
        later = S::ready_to_switch_on;
      }
      if (on) {
        now = opt == 0 ? S::switched_on : S::operation_enabled;
        later = S::switched_on;
      }
      break;
    case S::quick_stop_active:
      if (dv) now = later = S::switch_on_disabled;
      if (en) now = later = S::operation_enabled;
      break;
    case S::fault:
      if (reset) now = later = S::switch_on_disabled;
      break;
    default: break;
  }
  return Case{from, cw, qs, opt, now, later};
}

std::vector<Case> all_cases() {
  const std::uint16_t commands[] = {0x00, 0x02, 0x04, 0x06, 0x07, 0x0B, 0x0E, 0x0F, 0x80, 0x8F};
  std::vector<Case> v;
  for (S from : {S::switch_on_disabled, S::ready_to_switch_on, S::switched_on, S::operation_enabled,
                 S::quick_stop_active, S::fault}) {
    for (std::uint16_t cw : commands) {
      if (from == S::operation_enabled) {
        for (int qs : {0, 1, 2, 5, 6}) {
          for (int opt : {0, 1}) v.push_back(expect(from, cw, qs, opt));
        }
      } else if (from == S::quick_stop_active) {
        for (int qs : {5, 6}) v.push_back(expect(from, cw, qs, 1));
      } else {
        v.push_back(expect(from, cw, 1, 1));
      }
    }
  }
  return v;
}

// Brings a drive into `state`; OE and QSA with the axis turning at 500 rpm in profile velocity.
void bring_to(test::Drive& d, S state, int qs, int opt) {
  d.step();
  d.set(0x605A, 0, qs);
  d.set(0x605B, 0, opt);
  d.set(0x605C, 0, opt);
  d.set(0x6085, 0, 2000);
  switch (state) {
    case S::switch_on_disabled: return;
    case S::ready_to_switch_on: d.cw(0x06); return;
    case S::switched_on:
      d.cw(0x06);
      d.cw(0x07);
      return;
    case S::operation_enabled:
    case S::quick_stop_active:
      d.enable(3);
      d.set(0x60FF, 0, 500);
      d.step(400);
      ASSERT_NEAR(static_cast<double>(d.read(0x606C)), 500, 5);
      if (state == S::quick_stop_active) {
        d.cw(0x02);
        d.step(400);
        ASSERT_EQ(d.sw(), 0x0407);
      }
      return;
    case S::fault:
      d.core.inject(FaultCause::sensor);
      d.step();
      ASSERT_EQ(d.sw(), 0x0008);
      d.core.clear(FaultCause::sensor);
      return;
    default: FAIL();
  }
}

class Transitions : public ::testing::TestWithParam<Case> {};

TEST_P(Transitions, AfterWriteAndAfterRamp) {
  const Case& c = GetParam();
  test::Drive d;
  bring_to(d, c.from, c.qs_option, c.stop_option);
  if (HasFatalFailure()) return;
  d.cw(c.cw);
  EXPECT_EQ(d.core.state(), c.after_write) << to_string(d.core.state());
  EXPECT_EQ(d.sw() & 0x006F, base_of(c.after_write)) << std::hex << d.sw();
  d.step(1000);
  EXPECT_EQ(d.core.state(), c.after_ramp) << to_string(d.core.state());
  const std::uint16_t sw = d.sw();
  switch (c.after_ramp) {
    case S::switch_on_disabled:
    case S::ready_to_switch_on:
    case S::switched_on:
    case S::fault: EXPECT_EQ(sw & ~0x0100, base_of(c.after_ramp)) << std::hex << sw; break;
    case S::quick_stop_active: EXPECT_EQ(sw, 0x0407) << std::hex << sw; break;
    default: EXPECT_EQ(sw & 0x006F, 0x0027) << std::hex << sw; break;
  }
  EXPECT_EQ(d.read(0x6040), c.cw) << "the controlword is stored even when it has no transition";
}

INSTANTIATE_TEST_SUITE_P(AllStatesAllCommands, Transitions, ::testing::ValuesIn(all_cases()),
                         [](const auto& p) { return name_of(p.param); });

TEST(Transitions, TableIsLargeEnough) { EXPECT_GE(all_cases().size(), 150u); }

struct FaultReactionCase {
  int option;  // 605Eh
  bool ramp;   // FRA visible with a ramp
};

class FaultReaction : public ::testing::TestWithParam<FaultReactionCase> {};

TEST_P(FaultReaction, RampThenFaultAndCommandsIgnored) {
  const auto c = GetParam();
  test::Drive d;
  bring_to(d, S::operation_enabled, 1, 1);
  d.set(0x605E, 0, c.option);
  d.core.inject(FaultCause::external_torque);  // reaction per 605Eh
  d.step();
  if (!c.ramp) {
    EXPECT_EQ(d.core.state(), S::fault);
    EXPECT_EQ(d.sw() & ~0x0100, 0x0008);
    return;
  }
  EXPECT_EQ(d.core.state(), S::fault_reaction_active);
  EXPECT_EQ(d.sw(), 0x010F);
  for (std::uint16_t cw : {0x00, 0x02, 0x06, 0x07, 0x0F, 0x80}) {
    d.cw(cw);
    EXPECT_EQ(d.core.state(), S::fault_reaction_active) << "FRA ignores 0x" << std::hex << cw;
  }
  const std::uint64_t ms = d.step_until([&] { return d.core.state() == S::fault; }, 2000);
  // 500 rpm with 6084h = 1000 (300 ms) or 6085h = 2000 (150 ms)
  EXPECT_NEAR(static_cast<double>(ms), c.option == 1 ? 301 : 151, 2);
}

INSTANTIATE_TEST_SUITE_P(Options, FaultReaction,
                         ::testing::Values(FaultReactionCase{0, false}, FaultReactionCase{1, true},
                                           FaultReactionCase{2, true}, FaultReactionCase{3, true},
                                           FaultReactionCase{4, true}));

TEST(Transitions, ForcedTorqueOffIgnoresFaultReactionOption) {
  test::Drive d;
  bring_to(d, S::operation_enabled, 1, 1);
  d.core.inject(FaultCause::over_current);
  d.step();
  EXPECT_EQ(d.core.state(), S::fault);
}

TEST(Transitions, OptionCodesOutsideTheSetAreRefused) {
  test::Drive d;
  for (int v : {3, 4, 7, -1}) EXPECT_EQ(d.write(0x605A, 0, v), od::AbortCode::invalid_value) << v;
  EXPECT_EQ(d.write(0x605B, 0, 2), od::AbortCode::invalid_value);
  EXPECT_EQ(d.write(0x605C, 0, 2), od::AbortCode::invalid_value);
  EXPECT_EQ(d.write(0x605D, 0, 5), od::AbortCode::invalid_value);
  EXPECT_EQ(d.write(0x605E, 0, 5), od::AbortCode::invalid_value);
  EXPECT_EQ(d.write(0x605E, 0, 4), od::AbortCode::none);
}

TEST(Boot, StatuswordAtZeroAndOneMs) {
  test::Drive d;
  EXPECT_EQ(d.sw(), 0x0000);
  EXPECT_EQ(d.core.state(), S::not_ready_to_switch_on);
  d.cw(0x06);  // ignored in NRTSO
  EXPECT_EQ(d.core.state(), S::not_ready_to_switch_on);
  d.step();
  EXPECT_EQ(d.sw(), 0x0040);
  EXPECT_EQ(d.core.time_ms(), 1u);
  const auto changes = d.of<StateChanged>();
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0].transition, 1);
  EXPECT_TRUE(d.of<Emcy>().empty());
}

TEST(Boot, UnderVoltageBeforePowerOnFaultsAtTwoMs) {
  test::Drive d("MC349", {}, false);
  d.core.inject(FaultCause::under_voltage);
  d.core.power_on();
  d.step();
  EXPECT_EQ(d.sw(), 0x0040);
  d.step();
  EXPECT_EQ(d.sw(), 0x0008);
  const auto emcy = d.of<Emcy>();
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(emcy[0].bytes(), (std::array<std::uint8_t, 8>{0x21, 0x32, 0x05, 0, 0, 0, 0, 0}));
  d.step(10);
  EXPECT_EQ(d.of<Emcy>().size(), 1u) << "no repeat while the cause persists";
}

TEST(BackToBack, ShutdownSwitchOnEnableWithoutStep) {
  test::Drive d;
  d.step();
  d.cw(0x06);
  EXPECT_EQ(d.sw(), 0x0021);
  d.cw(0x07);
  EXPECT_EQ(d.sw(), 0x0023);
  d.cw(0x0F);
  EXPECT_EQ(d.core.state(), S::operation_enabled);
  EXPECT_EQ(d.sw() & 0x006F, 0x0027);
}

TEST(BackToBack, TwoSetPointEdgesWithinOneMillisecond) {
  test::Drive d;
  d.enable(1);
  d.set(0x607A, 0, 1000);
  d.cw(0x1F);
  d.set(0x607A, 0, 2000);
  d.cw(0x0F);
  d.cw(0x1F);
  const auto acc = d.of<SetpointAccepted>();
  ASSERT_EQ(acc.size(), 2u);
  EXPECT_EQ(acc[0].target_inc, 1000);
  EXPECT_EQ(acc[1].target_inc, 2000);
  EXPECT_TRUE(acc[1].buffered);
}

TEST(Transitions, SwitchOnPlusEnableFromReadyIsOneStatuswordEvent) {
  test::Drive d;
  d.step();
  d.cw(0x06);
  d.events.clear();
  d.cw(0x0F);
  const auto sw = d.of<StatuswordChanged>();
  ASSERT_EQ(sw.size(), 1u);
  EXPECT_EQ(sw[0].old_value, 0x0021);
  EXPECT_EQ(sw[0].new_value, 0x0027);
  const auto st = d.of<StateChanged>();
  ASSERT_EQ(st.size(), 1u);
  EXPECT_EQ(st[0].from, S::ready_to_switch_on);
  EXPECT_EQ(st[0].to, S::operation_enabled);
}

TEST(Transitions, FaultResetRefusedWhileCausePresentNoEmcy) {
  test::Drive d;
  d.step();
  d.core.inject(FaultCause::sensor);
  d.step();
  ASSERT_EQ(d.core.state(), S::fault);
  d.events.clear();
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), S::fault);
  EXPECT_TRUE(d.of<Emcy>().empty());
  const auto refused = d.of<FaultResetRefused>();
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].causes, std::vector<FaultCause>{FaultCause::sensor});
  d.cw(0x80);  // no new edge
  EXPECT_EQ(d.of<FaultResetRefused>().size(), 1u);
  d.core.clear(FaultCause::sensor);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), S::switch_on_disabled);
  EXPECT_EQ(d.sw(), 0x0040);
}

TEST(Transitions, PendingShutdownRampCancelledByEnable) {
  test::Drive d;
  bring_to(d, S::operation_enabled, 1, 1);
  d.cw(0x06);
  d.step(50);
  EXPECT_EQ(d.core.state(), S::operation_enabled);
  EXPECT_TRUE(d.sw() & 0x0100);
  d.cw(0x0F);
  d.step(1000);
  EXPECT_EQ(d.core.state(), S::operation_enabled);
}

TEST(Transitions, QuickStopRampTimingWith605A1) {
  // §4.5: from 1000 rpm with 6085h = 1000 … here 605Ah = 2 uses 6085h: demand 0 at the end of step
  // 600 after the write, SOD at the end of step 601
  test::Drive d;
  d.step();
  d.set(0x605A, 0, 2);
  d.enable(3);
  d.set(0x60FF, 0, 1000);
  d.step(700);
  d.cw(0x02);
  EXPECT_EQ(d.sw() & 0x016F, 0x0107);
  d.step(599);
  EXPECT_NE(d.read(0x606B), 0);
  d.step();
  EXPECT_EQ(d.read(0x606B), 0);
  EXPECT_EQ(d.core.state(), S::quick_stop_active);
  d.step();
  EXPECT_EQ(d.core.state(), S::switch_on_disabled);
}

}  // namespace
}  // namespace mcemu::core
