// Idle costs nothing (drive-core.md §2; README "Time"): DriveCore::quiet_steps() and skip() give
// exactly the object values, events and internal thermal state of 1 ms stepping, in every scenario
// below; and a drive at rest needs almost no full steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <tuple>

#include "tests/drive/core/core_fixture.hpp"
#include "tests/sim/trace_text.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

struct Action {
  std::uint64_t at;  // ms of simulated time since the start of the scenario (power cycles included)
  std::function<void(Drive&)> act;
};

struct Scenario {
  const char* name;
  std::vector<Action> actions;
  std::uint64_t end;
  bool idle;  // mostly at rest: the catch-up path must need far fewer full steps
  PlantConfig config{};
  std::vector<std::string> must_see{};  // events the scenario is about (it really gets there)
};

struct Trace {
  std::vector<std::string> trace;    // events with their time, full OD dumps every second
  std::vector<std::uint64_t> every;  // a hash of the live values after every single ms, per second
  std::uint64_t full = 0;
};

// stepping: 1 ms steps; skip_each_ms: skip(1) wherever quiet_steps() > 0 (checks the claim for
// every single step); catch_up: whole quiet stretches in one skip()
enum class Path { stepping, skip_each_ms, catch_up };

Trace run(const Scenario& s, const std::string& model, Path path) {
  const bool catch_up = path != Path::stepping;
  Drive d(model, s.config);
  Trace r;
  std::uint64_t elapsed = 0;
  const auto stamp = [&] { return std::to_string(elapsed) + "/" + std::to_string(d.core.time_ms()) + " "; };
  const auto record = [&] {
    d.collect();  // the fixture's writes collect their events into d.events
    for (const auto& e : d.events) r.trace.push_back(stamp() + sim::test::event_text(e));
    d.events.clear();
  };
  const auto checkpoint = [&] {
    char buf[160];
    std::snprintf(buf, sizeof buf, "T=%.17g E=%.17g U=%.17g state=%d raw=%lld", d.core.temperature_c(),
                  d.core.i2t_energy(), d.core.supply_voltage(), static_cast<int>(d.core.state()),
                  static_cast<long long>(d.core.raw_position_inc()));
    r.trace.push_back(stamp() + buf);
    for (auto& line : sim::test::od_dump(d.od)) r.trace.push_back(stamp() + line);
  };
  std::uint64_t hash = 1469598103934665603ULL;
  const auto sample = [&] {
    if (path == Path::catch_up) return;
    const auto fold = [&](std::uint64_t v) { hash = (hash ^ v) * 1099511628211ULL; };
    for (const auto& [i, sub] : std::vector<std::pair<std::uint16_t, std::uint8_t>>{{0x6041, 0},
                                                                                    {0x3401, 0x0A},
                                                                                    {0x3401, 0x0B},
                                                                                    {0x1002, 0},
                                                                                    {0x603F, 0},
                                                                                    {0x6064, 0},
                                                                                    {0x606C, 0},
                                                                                    {0x6078, 0},
                                                                                    {0x60FD, 0},
                                                                                    {0x6061, 0},
                                                                                    {0x3401, 0x23}}) {
      const auto v = d.od.read_number(i, sub);  // 3401h.23 (temperature read hook) on MCN23 only
      fold(v ? static_cast<std::uint64_t>(*v) : 0xDEAD);
    }
    const double t = d.core.temperature_c();
    std::uint64_t bits;
    std::memcpy(&bits, &t, sizeof bits);
    fold(bits);
  };
  const auto go_to = [&](std::uint64_t t) {
    while (elapsed < t) {
      if (catch_up) {
        const std::uint64_t q = d.core.quiet_steps();
        if (q > 0) {
          const std::uint64_t n = path == Path::skip_each_ms ? 1 : std::min(q, t - elapsed);
          d.core.skip(n);
          elapsed += n;
          sample();
          continue;
        }
      }
      d.core.step();
      ++elapsed;
      ++r.full;
      record();
      sample();
    }
  };
  record();
  std::size_t next = 0;
  for (std::uint64_t t = 0; t <= s.end; t += 1000) {
    while (next < s.actions.size() && s.actions[next].at <= t) {
      go_to(s.actions[next].at);
      checkpoint();
      s.actions[next].act(d);
      record();
      ++next;
    }
    go_to(t);
    checkpoint();
    if (path != Path::catch_up) r.every.push_back(hash);
  }
  return r;
}

void enable_pp(Drive& d) {
  d.set(0x6060, 0, 1);
  d.core.apply_mode_switch_now();
  d.cw(0x06);
  d.cw(0x07);
  d.cw(0x0F);
}

void go(Drive& d, std::int64_t target) {
  d.set(0x607A, 0, target);
  d.cw(0x1F);
  d.cw(0x0F);
}

PlantConfig with_noise() {
  PlantConfig c;
  c.noise.enabled = true;
  return c;
}
PlantConfig with_regen() {
  PlantConfig c;
  c.regen.enabled = true;
  return c;
}

const std::vector<Scenario>& scenarios() {
  static const std::vector<Scenario> all = {
      {"idle_from_power_on", {}, 60000, true},
      {"move_then_rest_and_warm_ambient",
       {{1, enable_pp},
        {2, [](Drive& d) { go(d, 300000); }},
        {4000, [](Drive& d) { d.cw(0x06); }},
        {5000, [](Drive& d) { d.core.set_ambient_temperature(45); }},
        {60000, [](Drive& d) { d.core.set_ambient_temperature(25); }}},
       120000,
       true,
       {},
       {"reached 1", "state 4>2 t8"}},
      {"over_temperature_and_reset",
       {{10, [](Drive& d) { d.core.set_ambient_temperature(2000); }},
        {40000, [](Drive& d) { d.core.set_ambient_temperature(20); }},
        {100000, [](Drive& d) { d.cw(0x80); }},
        {400000, [](Drive& d) { d.cw(0x00); }},
        {400001, [](Drive& d) { d.cw(0x80); }}},
       450000,
       true,
       {},
       {"fault 16912", "refused 1", "reset"}},
      {"under_voltage_and_reset",
       {{100, [](Drive& d) { d.core.set_supply_voltage(10); }},
        {5000, [](Drive& d) { d.core.set_supply_voltage(48); }},
        {6000, [](Drive& d) { d.cw(0x80); }}},
       12000,
       true,
       {},
       {"fault 12833", "reset"}},
      {"i2t_injected_decays",
       {{100, [](Drive& d) { d.core.inject(FaultCause::i2t); }}, {15000, [](Drive& d) { d.cw(0x80); }}},
       20000,
       true,
       {},
       {"fault 16928", "reset"}},
      {"fault_idle_then_reset",
       {{100, [](Drive& d) { d.core.inject(FaultCause::stroke); }}, {20000, [](Drive& d) { d.cw(0x80); }}},
       30000,
       true},
      {"injected_fault_while_idle",
       {{100, [](Drive& d) { d.core.inject(FaultCause::sensor); }},
        {9000, [](Drive& d) { d.core.clear(FaultCause::sensor); }},
        {9500, [](Drive& d) { d.cw(0x80); }}},
       12000,
       true},
      {"input_levels_and_small_load",
       {{100, [](Drive& d) { d.core.set_external_input_level(1, true); }},
        {200, [](Drive& d) { d.core.set_external_load(0.5 * d.core.plant_params().coulomb); }},
        {3000, [](Drive& d) { d.core.set_external_input_level(1, false); }}},
       6000,
       true},
      {"power_cycle_while_idle", {{20000, [](Drive& d) { d.core.power_on(); }}}, 40000, true},
      {"enabled_standing", {{1, enable_pp}}, 5000, false},
      {"noise_never_quiet", {}, 3000, false, with_noise()},
      {"regeneration_drains_then_rests",
       {{1,
         [](Drive& d) {
           d.set(0x6060, 0, 3);
           d.core.apply_mode_switch_now();
           d.cw(0x06);
           d.cw(0x07);
           d.cw(0x0F);
           d.set(0x60FF, 0, 3000);
         }},
        {1500, [](Drive& d) { d.set(0x60FF, 0, 0); }},
        {3000, [](Drive& d) { d.cw(0x06); }}},
       40000,
       true,
       with_regen()},
  };
  return all;
}

// MC349 has no temperature sensor (3401h.0A = 0); MCN23 has one and the 3401h.23 read hook.
class QuietEquivalence : public ::testing::TestWithParam<std::tuple<std::size_t, const char*>> {};

TEST_P(QuietEquivalence, CatchUpEqualsOneMillisecondSteps) {
  const Scenario& s = scenarios()[std::get<0>(GetParam())];
  const std::string model = std::get<1>(GetParam());
  const Trace a = run(s, model, Path::stepping);
  const Trace b = run(s, model, Path::catch_up);
  const Trace c = run(s, model, Path::skip_each_ms);
  ASSERT_EQ(a.trace.size(), b.trace.size()) << s.name;
  for (std::size_t i = 0; i < a.trace.size(); ++i) ASSERT_EQ(a.trace[i], b.trace[i]) << s.name << " line " << i;
  ASSERT_EQ(a.trace, c.trace) << s.name;
  for (std::size_t i = 0; i < a.every.size(); ++i) {
    ASSERT_EQ(a.every[i], c.every[i]) << s.name << ": the live values differ in second " << i;
  }
  std::printf("%s %s: %llu ms, full steps 1 ms path %llu, catch-up path %llu\n", model.c_str(), s.name,
              static_cast<unsigned long long>(s.end), static_cast<unsigned long long>(a.full),
              static_cast<unsigned long long>(b.full));
  EXPECT_EQ(a.full, s.end);
  for (const auto& what : s.must_see) {
    EXPECT_TRUE(std::any_of(a.trace.begin(), a.trace.end(),
                            [&](const std::string& line) { return line.find(" " + what) != std::string::npos; }))
        << s.name << " never shows " << what;
  }
  if (s.idle) {
    EXPECT_LT(b.full * 10, a.full) << s.name;
  } else {
    EXPECT_EQ(b.full, a.full) << s.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenarios, QuietEquivalence,
                         ::testing::Combine(::testing::Range<std::size_t>(0, 12), ::testing::Values("MC349", "MCN23")),
                         [](const auto& p) {
                           return std::string(std::get<1>(p.param)) + "_" + scenarios()[std::get<0>(p.param)].name;
                         });

TEST(QuietSteps, IdleDriveIsQuietForeverAfterItsFirstSteps) {
  Drive d;
  EXPECT_EQ(d.core.quiet_steps(), 0u);  // NRTSO: transition 1 is due
  d.step();
  d.step();
  EXPECT_EQ(d.core.quiet_steps(), DriveCore::k_forever);
}

TEST(QuietSteps, AnyCallBetweenStepsEndsTheQuiet) {
  const std::vector<std::pair<const char*, std::function<void(Drive&)>>> calls = {
      {"write 6040h", [](Drive& d) { d.cw(0x06); }},
      {"write 6060h", [](Drive& d) { d.set(0x6060, 0, 1); }},
      {"write same value through a hook", [](Drive& d) { d.cw(0x00); }},
      {"inject", [](Drive& d) { d.core.inject(FaultCause::sensor); }},
      {"supply", [](Drive& d) { d.core.set_supply_voltage(47); }},
      {"ambient", [](Drive& d) { d.core.set_ambient_temperature(30); }},
      {"load", [](Drive& d) { d.core.set_external_load(0); }},
      {"input", [](Drive& d) { d.core.set_external_input_level(2, true); }},
      {"home here", [](Drive& d) { d.core.set_home_here(); }},
      {"other object", [](Drive& d) { d.set(0x6081, 0, 1234); }},
  };
  for (const auto& [name, call] : calls) {
    Drive d;
    d.step(3);
    ASSERT_GT(d.core.quiet_steps(), 0u) << name;
    call(d);
    EXPECT_EQ(d.core.quiet_steps(), 0u) << name;
  }
}

// drive-core.md §10.11: a supply out of range for weeks (more than 2^31 ms) stays a fault and the
// drive stays quiet, through skipped stretches and full steps alike; it resets once the supply is back.
TEST(QuietSteps, UnderVoltageForWeeksStaysAFault) {
  Drive d;
  d.step(3);
  d.core.set_supply_voltage(10);
  d.step(3);
  ASSERT_EQ(d.core.state(), PdsState::fault);
  const std::uint64_t week = 7ULL * 24 * 3600 * 1000;
  for (int w = 0; w < 5; ++w) {  // 35 days: skipped weeks with full steps in between
    ASSERT_EQ(d.core.quiet_steps(), DriveCore::k_forever) << "week " << w;
    d.core.skip(week);
    d.step(2);
    d.cw(0x00);
    d.cw(0x80);  // a fault reset edge is refused while the cause is present
    EXPECT_EQ(d.core.state(), PdsState::fault) << "week " << w;
    d.step(1);
  }
  d.core.set_supply_voltage(48);
  d.step(2);
  d.cw(0x00);
  d.cw(0x80);
  d.step(1);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
}

TEST(QuietSteps, NotPoweredIsForever) {
  Drive d("MC349", {}, false);
  EXPECT_EQ(d.core.quiet_steps(), DriveCore::k_forever);
}

}  // namespace
}  // namespace mcemu::core
