// Faults, EMCY and injection (drive-core.md §11, §10.6, §10.7, §4.6, §15 items 14–16).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
using C = FaultCause;

enum class Reaction { torque_off, option, none };
enum class Reset { when_cleared, at_once, never, physical };

struct FaultCase {
  FaultCause cause;
  int bit;
  std::uint16_t code;
  std::uint8_t reg;
  Reaction reaction;
  Reset reset;
};

class EveryFault : public ::testing::TestWithParam<FaultCase> {};

// Brings the axis to OE in profile velocity at 500 rpm with 605Eh = 1.
void moving(Drive& d) {
  d.enable(3);
  d.set(0x60FF, 0, 500);
  d.step(400);
}

TEST_P(EveryFault, InjectionObjectsReactionAndReset) {
  const auto c = GetParam();
  Drive d;
  moving(d);
  d.events.clear();
  d.core.inject(c.cause);
  d.collect();
  const bool event_cause = c.reset == Reset::at_once;
  if (!event_cause) {
    EXPECT_EQ(d.core.state(), PdsState::operation_enabled) << "condition causes act at the next step 3";
    d.step();
    if (c.cause == C::under_voltage || c.cause == C::over_voltage) {
      EXPECT_EQ(d.core.state(), PdsState::operation_enabled) << "2-step supply debounce";
      d.step();
    }
  }
  if (c.reaction == Reaction::none) {
    EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
    EXPECT_EQ(d.read(0x1002), 1 << c.bit);
    EXPECT_EQ(d.sw() & 0x0080, 0x0080);
    EXPECT_EQ(d.read(0x1001), 0);
    EXPECT_TRUE(d.of<Emcy>().empty());
    d.core.clear(c.cause);
    d.step();
    EXPECT_EQ(d.read(0x1002), 0);
    EXPECT_EQ(d.sw() & 0x0080, 0);
    return;
  }
  const auto emcy = d.of<Emcy>();
  ASSERT_EQ(emcy.size(), 1u);
  EXPECT_EQ(emcy[0].bytes(),
            (std::array<std::uint8_t, 8>{static_cast<std::uint8_t>(c.code & 0xFF),
                                         static_cast<std::uint8_t>(c.code >> 8), c.reg, 0, 0, 0, 0, 0}));
  EXPECT_EQ(d.read(0x1001), c.reg);
  EXPECT_EQ(d.read(0x1002), 1 << c.bit);
  EXPECT_EQ(d.read(0x603F), c.code);
  EXPECT_EQ(d.read(0x1003, 0), 1);
  EXPECT_EQ(d.read(0x1003, 1), c.code);
  ASSERT_EQ(d.of<FaultRaised>().size(), 1u);
  EXPECT_EQ(d.of<FaultRaised>()[0].cause, c.cause);
  if (c.reaction == Reaction::torque_off) {
    EXPECT_EQ(d.core.state(), PdsState::fault);
    EXPECT_EQ(d.sw(), 0x0008);
  } else {
    EXPECT_EQ(d.core.state(), PdsState::fault_reaction_active);
    EXPECT_EQ(d.sw(), 0x010F) << "ramp visible with 605Eh = 1";
    d.step_until([&] { return d.core.state() == PdsState::fault; }, 1000);
    EXPECT_EQ(d.sw(), 0x0008);
  }
  d.step(1000);  // the axis coasts to rest
  EXPECT_EQ(d.of<Emcy>().size(), 1u) << "no repeated EMCY while the cause persists";
  // reset
  d.events.clear();
  d.cw(0x00);
  d.cw(0x80);
  if (c.reset == Reset::at_once) {
    EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  } else {
    EXPECT_EQ(d.core.state(), PdsState::fault) << "refused while the cause is present";
    EXPECT_TRUE(d.of<Emcy>().empty());
    ASSERT_EQ(d.of<FaultResetRefused>().size(), 1u);
    d.core.clear(c.cause);
    if (c.cause == FaultCause::i2t) d.step(3001);  // E falls by i_c²·Δt per step
    d.cw(0x00);
    d.cw(0x80);
    if (c.reset == Reset::never) {
      EXPECT_EQ(d.core.state(), PdsState::fault);
      d.core.power_on();
      d.step(2);
      EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled) << "only a power cycle clears it";
      return;
    }
    EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  }
  EXPECT_EQ(d.sw(), 0x0040);
  EXPECT_EQ(d.read(0x1002), 0);
  EXPECT_EQ(d.read(0x1001), 0);
  EXPECT_EQ(d.read(0x603F), c.code) << "603Fh keeps the last error code";
  const auto reset_emcy = d.of<Emcy>();
  ASSERT_EQ(reset_emcy.size(), 1u);
  EXPECT_EQ(reset_emcy[0].bytes(), (std::array<std::uint8_t, 8>{}));
  EXPECT_EQ(d.of<FaultResetDone>().size(), 1u);
  EXPECT_EQ(d.read(0x1003, 1), c.code) << "the reset EMCY is not recorded";
}

INSTANTIATE_TEST_SUITE_P(
    Catalogue, EveryFault,
    ::testing::Values(FaultCase{C::over_voltage, 0, 0x3211, 0x05, Reaction::option, Reset::physical},
                      FaultCase{C::under_voltage, 1, 0x3221, 0x05, Reaction::torque_off, Reset::physical},
                      FaultCase{C::ack_error, 2, 0x5200, 0x10, Reaction::option, Reset::when_cleared},
                      FaultCase{C::over_temperature, 3, 0x4210, 0x09, Reaction::option, Reset::physical},
                      FaultCase{C::i2t, 4, 0x4220, 0x09, Reaction::option, Reset::physical},
                      FaultCase{C::abort_connection, 5, 0x8130, 0x10, Reaction::option, Reset::at_once},
                      FaultCase{C::stroke, 6, 0x7121, 0x10, Reaction::option, Reset::at_once},
                      FaultCase{C::motor_communication, 7, 0x7510, 0x10, Reaction::torque_off, Reset::when_cleared},
                      FaultCase{C::sensor, 8, 0xFFF1, 0x10, Reaction::torque_off, Reset::when_cleared},
                      FaultCase{C::hw_sw_enable, 9, 0xFFF2, 0x10, Reaction::torque_off, Reset::at_once},
                      FaultCase{C::over_current, 11, 0x2220, 0x05, Reaction::torque_off, Reset::when_cleared},
                      FaultCase{C::external_torque, 12, 0xFFF4, 0x10, Reaction::option, Reset::when_cleared},
                      FaultCase{C::needs_reset, 13, 0xFFF5, 0x10, Reaction::torque_off, Reset::never},
                      FaultCase{C::sensor_warning, 16, 0, 0, Reaction::none, Reset::when_cleared}),
    [](const auto& p) { return std::string(to_string(p.param.cause)); });

TEST(FaultHistory, FourNewestFirstAndClearing) {
  Drive d;
  d.step();
  const FaultCause order[] = {C::sensor, C::over_current, C::ack_error, C::motor_communication, C::external_torque};
  for (FaultCause c : order) {
    d.core.inject(c);
    d.step();
    d.core.clear(c);
    d.cw(0x00);
    d.cw(0x80);
    ASSERT_EQ(d.core.state(), PdsState::switch_on_disabled);
  }
  EXPECT_EQ(d.read(0x1003, 0), 4);
  EXPECT_EQ(d.read(0x1003, 1), 0xFFF4);
  EXPECT_EQ(d.read(0x1003, 2), 0x7510);
  EXPECT_EQ(d.read(0x1003, 3), 0x5200);
  EXPECT_EQ(d.read(0x1003, 4), 0x2220);
  EXPECT_EQ(d.write(0x1003, 0, 1), od::AbortCode::invalid_value);
  EXPECT_EQ(d.write(0x1003, 1, 0), od::AbortCode::read_only);
  d.set(0x1003, 0, 0);
  EXPECT_EQ(d.read(0x1003, 0), 0);
  EXPECT_EQ(d.read(0x1003, 1), 0);
  EXPECT_EQ(d.read(0x1003, 4), 0);
}

TEST(Faults, SecondCauseInFaultSendsItsOwnEmcy) {
  Drive d;
  d.step();
  d.core.inject(C::sensor);
  d.step();
  d.core.inject(C::over_current);
  d.step();
  EXPECT_EQ(d.of<Emcy>().size(), 2u);
  EXPECT_EQ(d.read(0x1002), (1 << 8) | (1 << 11));
  EXPECT_EQ(d.read(0x1001), 0x15);
  EXPECT_EQ(d.read(0x603F), 0x2220);
}

TEST(Faults, ErrorBitStaysAfterConditionGoesAway) {
  Drive d;
  d.step();
  d.core.set_supply_voltage(17);
  d.step(2);
  EXPECT_EQ(d.core.state(), PdsState::fault);
  d.core.set_supply_voltage(18.5);
  d.step();
  EXPECT_EQ(d.read(0x1002), 2) << "kept until a successful reset";
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::fault) << "reset needs U ≥ uv + 1 V";
  d.core.set_supply_voltage(19);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
}

TEST(Faults, SupplyDebounceTwoSteps) {
  Drive d;
  d.step();
  d.core.set_supply_voltage(61);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::fault);
  EXPECT_EQ(d.read(0x603F), 0x3211);
  d.core.set_supply_voltage(58.5);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::fault);
  d.core.set_supply_voltage(58);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
}

// ---- block detection (§10.6, §15 item 15)

void towards_obstacle(Drive& d, ObstacleId* id = nullptr) {
  const ObstacleId o = d.core.add_obstacle({30000, +1});
  if (id) *id = o;
  d.enable(1);
  d.set(0x607A, 0, 65536);
  d.cw(0x2F);
  d.cw(0x3F);
}

TEST(BlockDetection, StrokeFaultAfter101MsOfSaturation) {
  Drive d;
  towards_obstacle(d);
  const std::uint64_t sat = d.step_until([&] { return std::llabs(d.read(0x6078)) == 1000; }, 2000);
  ASSERT_LT(sat, 2000u);
  const std::uint64_t fault = d.step_until([&] { return d.read(0x603F) == 0x7121; }, 2000);
  EXPECT_NEAR(static_cast<double>(fault), 101, 2);
  EXPECT_EQ(d.core.raw_position_inc(), 30000);
  d.step_until([&] { return d.core.state() == PdsState::fault; }, 2000);
  EXPECT_EQ(d.core.state(), PdsState::fault);
}

TEST(BlockDetection, MaskedBlockPushesWithReducedTorqueAndContinues) {
  Drive d;
  ObstacleId id = 0;
  d.set(0x3401, 0x1A, 15);
  d.set(0x6073, 0, 300);
  towards_obstacle(d, &id);
  d.step(1500);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(d.read(0x1002), 0);
  EXPECT_NEAR(static_cast<double>(d.read(0x6078)), 300, 2);
  EXPECT_EQ(d.core.raw_position_inc(), 30000);
  d.core.remove_obstacle(id);
  d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 10000);
  EXPECT_EQ(d.read(0x6064), 65536);
}

TEST(BlockDetection, StrokeOption1SendsEmcyOnlyAndHolds) {
  Drive d;
  d.set(0x6059, 1, 1);
  towards_obstacle(d);
  d.step(1000);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  const auto emcy = d.of<Emcy>();
  ASSERT_GE(emcy.size(), 1u);
  EXPECT_EQ(emcy[0].code, 0x7121);
  EXPECT_EQ(d.read(0x1002), 0);
  EXPECT_EQ(d.read(0x1003, 0), 0);
  EXPECT_EQ(d.read(0x603F), 0);
  EXPECT_LT(std::llabs(d.read(0x6078)), 1000) << "the motion was aborted: no longer pushing at the limit";
}

TEST(BlockDetection, StrokeOptions2And3MoveAway) {
  for (int option : {2, 3}) {
    Drive d;
    d.set(0x6059, 1, option);
    d.set(0x6059, 2, option == 2 ? 1000 : -5000);
    towards_obstacle(d);
    d.step(3000);
    EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
    EXPECT_EQ(d.of<Emcy>().size(), 1u);
    EXPECT_EQ(d.read(0x60FC), option == 2 ? 1000 : 25000) << option;
  }
}

TEST(FollowingError, FaultOnModelsWithMonitor) {
  Drive d("MC632");
  d.set(0x3401, 0x1A, 7);  // blocks ignored, following error monitored
  towards_obstacle(d);
  d.set(0x607A, 0, 10 * 65536);
  d.cw(0x2F);
  d.cw(0x3F);
  d.step_until([&] { return d.core.state() == PdsState::fault; }, 5000);
  EXPECT_EQ(d.read(0x603F), 0x7121);
  Drive m("MC632");
  m.set(0x3401, 0x1A, 15);
  towards_obstacle(m);
  m.step(2000);
  EXPECT_EQ(m.core.state(), PdsState::operation_enabled);
}

// ---- thermal and I²t (§10.7, §15 item 16)

TEST(Thermal, I2tTripsAfterTwoSecondsAtFullCurrent) {
  Drive d;
  d.set(0x3401, 0x1A, 15);
  towards_obstacle(d);
  const std::uint64_t full = d.step_until([&] { return std::llabs(d.read(0x6078)) == 1000; }, 2000);
  ASSERT_LT(full, 2000u);
  const std::uint64_t trip = d.step_until([&] { return d.read(0x603F) == 0x4220; }, 5000);
  EXPECT_NEAR(static_cast<double>(trip), 2000, 5);
  d.step_until([&] { return d.core.state() == PdsState::fault; }, 1000);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::fault) << "E > E_max/2";
  d.step(3100);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
}

TEST(Thermal, I2tNeverAtThirtyPercent) {
  Drive d;
  d.set(0x3401, 0x1A, 15);
  d.set(0x6073, 0, 300);
  towards_obstacle(d);
  d.step(10000);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(d.core.i2t_energy(), 0);
}

TEST(Thermal, OverTemperatureFromAmbient) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::tau_th_s, 6);
  Drive d("MC349", cfg);
  d.core.set_ambient_temperature(150);
  EXPECT_NEAR(d.core.temperature_c(), 31, 1e-9);
  const std::uint64_t trip = d.step_until([&] { return d.read(0x603F) == 0x4210; }, 10000);
  EXPECT_NEAR(static_cast<double>(trip), 5998, 6);
  EXPECT_EQ(d.core.state(), PdsState::fault);
  d.core.set_ambient_temperature(25);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::fault);
  d.step_until([&] { return d.core.temperature_c() <= 100; }, 100000);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
}

TEST(Thermal, TemperatureObjectOnModelsWithSensor) {
  Drive with("MC632");
  with.step();
  EXPECT_EQ(with.read(0x3401, 0x0A), 31);  // 25 °C + 2 K/W · 3 W
  with.core.inject(C::over_temperature);
  with.step();
  EXPECT_EQ(with.read(0x3401, 0x0A), 115);
  Drive without("MC349");
  without.step();
  EXPECT_EQ(without.read(0x3401, 0x0A), 0);
}

// ---- enable checks (§4.6)

TEST(Enable, HardwareEnableInput) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::hw_enable_fitted, true);
  Drive d("MC632", cfg);
  d.step();
  d.cw(0x06);
  d.cw(0x07);
  EXPECT_EQ(d.core.state(), PdsState::fault);
  EXPECT_EQ(d.read(0x603F), 0xFFF2);
  d.cw(0x80);
  ASSERT_TRUE(d.core.set_external_input_level(10, true));
  d.enable(1);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  d.core.set_external_input_level(10, false);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::fault);
}

TEST(Enable, HardwareEnableOnPowerPinModelIsAConfigError) {
  PlantConfig cfg;
  cfg.plant.set(&model::Plant::hw_enable_fitted, true);
  const auto preset = test::preset_of("MC349");
  od::ObjectDictionary od(preset);
  EXPECT_THROW(DriveCore(preset, od, cfg), std::invalid_argument);
}

TEST(Enable, SoftwareEnableFunctionNine) {
  Drive d;
  d.set(0x3511, 1, 0x0900);
  d.step();
  d.cw(0x06);
  d.cw(0x0F);
  EXPECT_EQ(d.core.state(), PdsState::fault) << "IN1 low: switch-on refused with FFF2h";
  d.cw(0x80);
  d.core.set_external_input_level(1, true);
  d.enable(3);
  ASSERT_EQ(d.core.state(), PdsState::operation_enabled);
  d.set(0x60FF, 0, 500);
  d.step(400);
  d.events.clear();
  d.core.set_external_input_level(1, false);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled) << "605Ch = 1: ramp first";
  d.step_until([&] { return d.core.state() != PdsState::operation_enabled; }, 1000);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  EXPECT_TRUE(d.of<Emcy>().empty());
  EXPECT_EQ(d.of<StateChanged>().back().transition, 9);
  EXPECT_EQ(d.read(0x6060), 3);
  // low-active variant
  d.set(0x3511, 1, 0x0009);
  d.cw(0x06);
  d.cw(0x07);
  EXPECT_EQ(d.core.state(), PdsState::switched_on);
}

// The core keeps what 3511h…351Ah require for Software Enable until a setting changes
// (ObjectDictionary::settings_generation): a function 9 that arrives while the drive runs — by a
// write or by a bulk load — still takes the enable away in the next steps.
TEST(Enable, SoftwareEnableFunctionArrivingWhileEnabled) {
  for (const bool bulk : {false, true}) {
    Drive d;
    d.enable(3);
    d.set(0x60FF, 0, 500);
    d.step(50);
    ASSERT_EQ(d.core.state(), PdsState::operation_enabled);
    ASSERT_TRUE(d.core.software_enabled());
    if (bulk) {
      const std::array<od::StoredValue, 1> load{od::StoredValue{0x3511, 1, std::int64_t{0x0900}}};
      ASSERT_TRUE(d.od.load_values(load).empty());
    } else {
      d.set(0x3511, 1, 0x0900);  // IN1 is low
    }
    EXPECT_FALSE(d.core.software_enabled()) << (bulk ? "load" : "write");
    d.step(2000);
    EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled) << (bulk ? "load" : "write");
    d.core.set_external_input_level(1, true);
    EXPECT_TRUE(d.core.software_enabled()) << "the input level is read every time";
  }
}

// ---- connection abort (§11.6)

TEST(ConnectionLost, OptionCodes) {
  struct Row {
    int option;
    PdsState expect;
  };
  for (const Row r : {Row{0, PdsState::operation_enabled}, Row{1, PdsState::fault},
                      Row{2, PdsState::switch_on_disabled}, Row{3, PdsState::quick_stop_active}}) {
    Drive d;
    d.set(0x6007, 0, r.option);
    d.set(0x605A, 0, 6);
    d.enable(1);
    d.core.connection_lost();
    d.step();
    EXPECT_EQ(d.core.state(), r.expect) << r.option;
    EXPECT_EQ(d.read(0x6040), 0x0F) << "6040h is not modified";
  }
}

TEST(Injection, EventCauseBeforeFirstStepIsRaisedInSecondStep) {
  Drive d;
  d.core.inject(C::stroke);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  d.step();
  EXPECT_EQ(d.core.state(), PdsState::fault);
  EXPECT_EQ(d.read(0x603F), 0x7121);
}

TEST(Injection, SurvivesPowerCycleExceptNeedsReset) {
  Drive d;
  d.core.inject(C::sensor);
  d.core.inject(C::needs_reset);
  d.core.power_on();
  EXPECT_TRUE(d.core.injected(C::sensor));
  EXPECT_FALSE(d.core.injected(C::needs_reset));
}

TEST(Injection, ExternalLoadMovesAnUnpoweredAxis) {
  Drive d;
  d.step();
  d.core.set_external_load(0.05);
  d.step(100);
  EXPECT_GT(d.read(0x6063), 1000);
  EXPECT_TRUE(d.sw() & 0x0100) << "moving bit follows the actual velocity in every state but F";
}

}  // namespace
}  // namespace mcemu::core
