// Determinism (drive-core.md §1.2, §15 item 17), events (§13), the inputs observer and 60FDh
// (§10.9), and the mirror entries computed on read (§14.1).
#include <gtest/gtest.h>

#include <sstream>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

std::string describe(const Event& e) {
  std::ostringstream o;
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, StatuswordChanged>) o << "sw " << v.old_value << ">" << v.new_value;
        if constexpr (std::is_same_v<T, StateChanged>) o << "state " << v.transition;
        if constexpr (std::is_same_v<T, ModeDisplayChanged>) o << "mode " << int(v.mode);
        if constexpr (std::is_same_v<T, Emcy>) o << "emcy " << v.code << "/" << int(v.reg);
        if constexpr (std::is_same_v<T, FaultRaised>) o << "fault " << v.code;
        if constexpr (std::is_same_v<T, FaultResetDone>) o << "reset";
        if constexpr (std::is_same_v<T, FaultResetRefused>) o << "refused " << v.causes.size();
        if constexpr (std::is_same_v<T, SetpointAccepted>) o << "sp " << v.target_inc << " " << v.buffered;
        if constexpr (std::is_same_v<T, SetpointRejected>) o << "rejected";
        if constexpr (std::is_same_v<T, TargetReached>) o << "reached " << int(v.mode);
        if constexpr (std::is_same_v<T, HomingFinished>) o << "homed " << int(v.method) << v.ok;
        if constexpr (std::is_same_v<T, InternalLimit>) o << "limit " << v.active;
        if constexpr (std::is_same_v<T, InputsChanged>) o << "in " << v.old_value << ">" << v.new_value;
        if constexpr (std::is_same_v<T, PowerStage>) o << "power " << v.on;
        if constexpr (std::is_same_v<T, Diagnostic>) o << "diag " << v.text;
      },
      e);
  return o.str();
}

std::vector<std::pair<std::string, std::string>> snapshot(const od::ObjectDictionary& od) {
  std::vector<std::pair<std::string, std::string>> out;
  od.for_each([&](const od::EntryInfo& i, const od::Value& v) {
    std::ostringstream k;
    k << std::hex << i.index << "." << int(i.sub);
    std::ostringstream s;
    if (const auto* n = std::get_if<std::int64_t>(&v)) {
      s << *n;
    } else {
      s << std::get<std::string>(v);
    }
    out.emplace_back(k.str(), s.str());
  });
  return out;
}

// 60 s: buffered moves, a velocity phase, an obstacle, a fault and its reset, homing.
void scenario(Drive& d, bool single_steps) {
  PlantConfig cfg;
  d.enable(1);
  d.set(0x6081, 0, 1500);
  for (int i = 1; i <= 15; ++i) {
    d.cw(0x0F);
    d.set(0x607A, 0, (i % 2 ? 1 : -1) * i * 20000);
    d.cw(i % 3 == 0 ? 0x21F : 0x1F);
  }
  const auto run = [&](std::uint64_t n) {
    if (single_steps) {
      d.step(n);
    } else {
      d.core.step(n);
      d.collect();
    }
  };
  run(15000);
  d.set(0x6060, 0, 3);
  d.set(0x60FF, 0, -700);
  run(5000);
  d.core.add_obstacle({d.core.raw_position_inc() - 200000, -1});
  run(10000);
  d.cw(0x00);
  d.cw(0x80);
  d.core.inject(FaultCause::sensor);
  run(100);
  d.core.clear(FaultCause::sensor);
  d.cw(0x00);
  d.cw(0x80);
  d.set(0x6060, 0, 6);
  d.set(0x6098, 0, 35);
  d.cw(0x06);
  d.cw(0x07);
  d.cw(0x0F);
  d.cw(0x1F);
  run(60000 - d.core.time_ms());
}

TEST(Determinism, SameScenarioTwiceAndStepNVersusSingleSteps) {
  Drive a;
  Drive b;
  Drive c;
  scenario(a, true);
  scenario(b, true);
  scenario(c, false);
  EXPECT_EQ(a.core.time_ms(), 60000u);
  const auto sa = snapshot(a.od);
  EXPECT_EQ(sa, snapshot(b.od));
  EXPECT_EQ(sa, snapshot(c.od));
  std::vector<std::string> ea, eb, ec;
  for (const auto& e : a.events) ea.push_back(describe(e));
  for (const auto& e : b.events) eb.push_back(describe(e));
  for (const auto& e : c.events) ec.push_back(describe(e));
  EXPECT_EQ(ea, eb);
  EXPECT_EQ(ea, ec);
  EXPECT_GT(ea.size(), 100u);
  EXPECT_EQ(a.core.raw_position_inc(), c.core.raw_position_inc());
}

TEST(Events, StatuswordChangesChainAndPowerStage) {
  Drive d;
  d.enable(1);
  d.step(150);
  d.set(0x607A, 0, 5000);
  d.cw(0x1F);
  d.step(600);
  d.cw(0x06);
  d.step(5);
  std::uint16_t last = 0;
  for (const auto& e : d.of<StatuswordChanged>()) {
    EXPECT_EQ(e.old_value, last);
    last = e.new_value;
  }
  EXPECT_EQ(last, d.sw());
  const auto power = d.of<PowerStage>();
  ASSERT_EQ(power.size(), 2u);
  EXPECT_TRUE(power[0].on);
  EXPECT_FALSE(power[1].on);
  EXPECT_EQ(d.of<ModeDisplayChanged>().size(), 1u);
  EXPECT_EQ(d.of<TargetReached>().size(), 2u) << "after enable and after the move";
}

TEST(Inputs, ExternalLevelsObserverAndVirtualInputs) {
  Drive d;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> seen;
  d.core.set_inputs_observer([&](std::uint32_t o, std::uint32_t n) { seen.emplace_back(o, n); });
  d.step();
  EXPECT_FALSE(d.core.set_external_input_level(5, true)) << "MC349 has IN1–IN4";
  ASSERT_TRUE(d.core.set_external_input_level(2, true));
  EXPECT_EQ(d.read(0x60FD), 0x00020000) << "current at once";
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0], (std::pair<std::uint32_t, std::uint32_t>{0, 0x00020000}));
  d.set(0x3510, 1, 0x02000001);  // IN10 virtual; bit 0 is masked out
  d.core.recompute_inputs();
  EXPECT_EQ(d.read(0x60FD), 0x02020000);
  EXPECT_EQ(seen.size(), 2u);
  d.core.recompute_inputs();
  EXPECT_EQ(seen.size(), 2u) << "no call without a change";
  d.collect();
  EXPECT_EQ(d.of<InputsChanged>().size(), 2u);
  EXPECT_THROW(d.core.set_inputs_observer([](std::uint32_t, std::uint32_t) {}), std::logic_error)
      << "one observer; a second would silently replace the I/O functions";
  ASSERT_TRUE(d.core.set_external_input_level(1, true));
  EXPECT_EQ(seen.size(), 3u) << "the first observer still runs";
}

TEST(Inputs, CombinedPinSeesItsOutput) {
  Drive d("MC632");
  d.step();
  d.set(0x60FE, 1, 0x00010000);  // OUT1
  d.core.recompute_inputs();
  EXPECT_EQ(d.read(0x60FD), 0x00010000);
  Drive m("MC349");  // separate output pins
  m.step();
  m.set(0x60FE, 1, 0x00010000);
  m.core.recompute_inputs();
  EXPECT_EQ(m.read(0x60FD), 0);
}

TEST(Inputs, PositionSwitchSeenInTheStepItIsEntered) {
  PlantConfig cfg;
  cfg.position_switches.push_back({3, 30000, 40000});
  Drive d("MC349", cfg);
  std::vector<std::uint32_t> words;
  d.core.set_inputs_observer([&](std::uint32_t, std::uint32_t n) { words.push_back(n); });
  d.enable(1);
  d.set(0x607A, 0, 65536);
  d.cw(0x1F);
  bool in_range_checked = false;
  for (int k = 0; k < 600; ++k) {
    d.step();
    const std::int64_t raw = d.core.raw_position_inc();
    EXPECT_EQ((d.read(0x60FD) >> 18) & 1, raw >= 30000 && raw <= 40000 ? 1 : 0) << raw;
    in_range_checked = in_range_checked || (raw >= 30000 && raw <= 40000);
  }
  EXPECT_TRUE(in_range_checked);
  ASSERT_EQ(words.size(), 2u);
  EXPECT_EQ(words[0], 0x00040000u);
  EXPECT_EQ(words[1], 0u);
}

TEST(Inputs, PowerOnWordIsNotReported) {
  Drive d("MC349", {}, false);
  int calls = 0;
  d.core.set_inputs_observer([&](std::uint32_t, std::uint32_t) { ++calls; });
  d.core.set_external_input_level(1, true);
  d.core.power_on();
  EXPECT_EQ(d.read(0x60FD), 0x00010000);
  EXPECT_EQ(calls, 0);
}

TEST(Mirrors, ComputedOnRead) {
  Drive mc("MC349");
  mc.enable(3);
  mc.core.set_external_load(-0.1);
  mc.set(0x60FF, 0, 1000);
  mc.step(800);
  EXPECT_EQ(mc.read(0x3401, 0x1D), mc.read(0x6063));
  // 0.1 N·m against 1000 rpm ≈ 10.5 W mechanical + friction + copper loss
  EXPECT_NEAR(static_cast<double>(mc.read(0x3401, 0x0B)), 17, 3);
  Drive ae("MC349_AE", {}, false);
  ae.core.power_on(PowerOnState{-70000, 0});
  EXPECT_EQ(ae.read(0x3401, 0x1F), -2);
  EXPECT_EQ(ae.read(0x3401, 0x20), 61072);
  Drive n23("MCN23");
  n23.step();
  EXPECT_EQ(n23.read(0x3401, 0x23), 33);  // 25 °C + 2.5 K/W · 3 W = 32.5 → 33
  EXPECT_EQ(n23.read(0x5000, 0x03), n23.read(0x6063));
  EXPECT_EQ(n23.read(0x5002, 0x0E), n23.read(0x6063));
  EXPECT_EQ(n23.read(0x5000, 0x05), 0);
  EXPECT_EQ(n23.read(0x5000, 0x04), 0);
}

TEST(Lifetime, DestroyedCoreLeavesAPlainDictionary) {
  const auto preset = test::preset_of("MC349");
  od::ObjectDictionary od(preset);
  {
    DriveCore core(preset, od);
    core.power_on();
    core.step();
    EXPECT_EQ(od.write(0x6040, 0, od::Value{std::int64_t{6}}, od::Origin::sdo), od::AbortCode::none);
    EXPECT_EQ(*od.read_number(0x6041, 0), 0x21);
  }
  EXPECT_EQ(od.write(0x6040, 0, od::Value{std::int64_t{7}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_EQ(*od.read_number(0x6041, 0), 0x21) << "no hook runs any more";
  EXPECT_EQ(*od.read_number(0x3401, 0x1D), 0) << "no read hook either";
  DriveCore again(preset, od);  // a new core can take over the same dictionary
  again.power_on();
  again.step();
  EXPECT_EQ(*od.read_number(0x6041, 0), 0x40);
}

TEST(PowerOn, IncrementalStartsAtZeroAbsoluteKeepsHomeOffset) {
  Drive re("MC349", {}, false);
  re.core.power_on(PowerOnState{123456, 999});
  EXPECT_EQ(re.read(0x6063), 0);
  EXPECT_EQ(re.core.home_offset_inc(), 123456);
  Drive ae("MC349_AE", {}, false);
  ae.core.power_on(PowerOnState{123456, 1000});
  EXPECT_EQ(ae.read(0x6063), 122456);
  EXPECT_EQ(ae.core.raw_position_inc(), 123456);
  Drive flat("MCFLAT");
  EXPECT_EQ(flat.core.raw_position_inc(), 100000) << "middle of the stroke";
}

TEST(PowerOn, ResetsVolatileObjectsAndTime) {
  Drive d;
  d.enable(1);
  d.core.inject(FaultCause::sensor);
  d.step(10);
  d.core.clear(FaultCause::sensor);
  d.core.power_on();
  EXPECT_EQ(d.core.time_ms(), 0u);
  EXPECT_EQ(d.read(0x6041), 0);
  EXPECT_EQ(d.read(0x1002), 0);
  EXPECT_EQ(d.read(0x1001), 0);
  EXPECT_EQ(d.read(0x603F), 0);
  EXPECT_EQ(d.read(0x1003, 0), 0);
  EXPECT_EQ(d.read(0x1003, 1), 0);
  EXPECT_EQ(d.read(0x6061), 0);
  d.step();
  EXPECT_EQ(d.sw(), 0x0040);
}

}  // namespace
}  // namespace mcemu::core

namespace mcemu::core {
namespace {

// The trace text of every event kind (web.md §8.6, channel drive): name of §13 and payload.
TEST(EventText, EveryKind) {
  const std::vector<std::pair<Event, std::string>> rows = {
      {StatuswordChanged{0x0040, 0x0421}, "StatuswordChanged 0040h -> 0421h"},
      {StateChanged{PdsState::switched_on, PdsState::operation_enabled, 4},
       "StateChanged switched_on -> operation_enabled (transition 4)"},
      {ModeDisplayChanged{-1}, "ModeDisplayChanged -1"},
      {Emcy{0x3221, 0x05, {1, 2, 3, 4, 5}}, "Emcy 3221h reg 05h data 2132050102030405"},
      {FaultRaised{FaultCause::under_voltage, 0x3221}, "FaultRaised under_voltage 3221h"},
      {FaultResetDone{}, "FaultResetDone"},
      {FaultResetRefused{{FaultCause::stroke, FaultCause::sensor}}, "FaultResetRefused stroke,sensor"},
      {SetpointAccepted{-163840, true}, "SetpointAccepted -163840 buffered"},
      {SetpointRejected{SetpointRejectReason::buffer_full}, "SetpointRejected buffer_full"},
      {TargetReached{1}, "TargetReached mode 1"},
      {HomingFinished{35, false}, "HomingFinished method 35 failed"},
      {InternalLimit{true}, "InternalLimit on"},
      {InputsChanged{0, 0x10000}, "InputsChanged 00000000h -> 00010000h"},
      {PowerStage{false}, "PowerStage off"},
      {Diagnostic{DiagnosticLevel::warning, "set-point ignored"}, "Diagnostic warning set-point ignored"},
  };
  EXPECT_EQ(rows.size(), std::variant_size_v<Event>) << "one row per kind";
  for (const auto& [e, text] : rows) EXPECT_EQ(event_text(e), text);
}

}  // namespace
}  // namespace mcemu::core
