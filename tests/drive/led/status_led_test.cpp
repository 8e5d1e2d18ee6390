// The green STATUS LED (morse-led.md §2–§4, §7 items 1, 2, 4, 5): schedule, decode, live sampling in
// simulated time, fault text at repetition boundaries, power cycle.
#include "drive/led/status_led.hpp"

#include <gtest/gtest.h>

#include <numeric>

#include "drive/led/leds.hpp"
#include "tests/drive/core/core_fixture.hpp"
#include "tests/drive/led/morse_decoder.hpp"

namespace mcemu::led {
namespace {

using test::decode_elements;
using test::decode_runs;
using test::run_lengths;

constexpr std::uint64_t T = StatusLed::k_unit_ms;

struct Case {
  Ipv4 ip;
  std::optional<std::uint16_t> fault;
  const char* text;
  std::uint64_t units;
};

class ScheduleTest : public ::testing::TestWithParam<Case> {};

TEST_P(ScheduleTest, DecodesToTheTextWithTheSpecifiedLength) {
  const Case& c = GetParam();
  const Schedule s = make_schedule(StatusLed::message(c.ip, c.fault), StatusLed::k_unit_ms);
  EXPECT_EQ(s.text, c.text);
  EXPECT_EQ(decode_elements(s.elements, T), c.text);
  if (c.units != 0) {  // 0: no number in the spec
    EXPECT_EQ(s.cycle_ms, c.units * T);
  }
  EXPECT_EQ(std::accumulate(s.elements.begin(), s.elements.end(), std::uint64_t{0}), s.cycle_ms);
  ASSERT_EQ(s.elements.size() % 2, 0u);
  EXPECT_EQ(s.elements.back(), 3 * T);  // the gap after ':' is the only pause between repetitions
  // dots, dashes, element and character gaps only: no word gap, the message has no spaces
  for (std::size_t i = 0; i < s.elements.size(); ++i) EXPECT_TRUE(s.elements[i] == T || s.elements[i] == 3 * T) << i;
}

INSTANTIATE_TEST_SUITE_P(Messages, ScheduleTest,
                         ::testing::Values(Case{{192, 168, 2, 150}, std::nullopt, "MC+IP192+168+2+150:", 310},
                                           Case{{10, 0, 0, 1}, std::nullopt, "MC+IP10+0+0+1:", 234},
                                           Case{{192, 168, 2, 150}, 0x7121, "MC+IP192+168+2+150+ERR7121:", 424},
                                           Case{{255, 255, 255, 255}, 0xABCD, "MC+IP255+255+255+255+ERRABCD:", 0}));

TEST(ScheduleTest, FactoryMessageNumbers) {
  const Schedule s = make_schedule("MC+IP192+168+2+150:", StatusLed::k_unit_ms);
  EXPECT_EQ(s.cycle_ms, 37200u);
  EXPECT_EQ(s.on_ms, 22080u);
  // worked start of §4: M = 3,1,3 ; gap 3 ; C = 3,1,1,1,3,1,1 ; gap 3 ; + = 1,1,3,1,1,1,3,1,1
  const std::vector<std::uint32_t> start = {3, 1, 3, 3, 3, 1, 1, 1, 3, 1, 1, 3, 1, 1, 3, 1, 1, 1, 3, 1, 1};
  for (std::size_t i = 0; i < start.size(); ++i) EXPECT_EQ(s.elements[i], start[i] * T) << i;
}

TEST(ScheduleTest, RejectsCharactersOutsideTheTable) {
  EXPECT_THROW(make_schedule("MC IP", T), std::invalid_argument);
  EXPECT_THROW(make_schedule("mc", T), std::invalid_argument);
  EXPECT_THROW(make_schedule("", T), std::invalid_argument);
  EXPECT_THROW(make_schedule("G", T), std::invalid_argument);
}

// §7.2: a drive stepped 1 ms at a time, the LED read at t = 0 and after every step.
TEST(StatusLedTest, LiveSamplingFromPowerUpDecodesTwice) {
  core::test::Drive d;
  Leds leds;
  leds.power_up(address_of(d.od));
  const std::uint64_t cycle = leds.green.view(0).schedule->cycle_ms;
  ASSERT_EQ(cycle, 37200u);
  std::vector<bool> samples{leds.green.on(d.core.time_ms())};
  for (std::uint64_t i = 0; i < 2 * cycle; ++i) {
    d.step();
    leds.update_status(d.core, d.od);
    samples.push_back(leds.green.on(d.core.time_ms()));
  }
  const auto runs = run_lengths(samples);
  // the last run is the one sample of the third repetition's first element, cut by the window
  const std::vector<std::pair<bool, std::uint64_t>> whole(runs.begin(), runs.end() - 1);
  EXPECT_EQ(decode_runs(whole, T), "MC+IP192+168+2+150:MC+IP192+168+2+150:");
  ASSERT_TRUE(runs.front().first);
  for (std::size_t i = 0; i + 1 < runs.size(); ++i) {
    EXPECT_TRUE(runs[i].second == T || runs[i].second == 3 * T) << "run " << i << " = " << runs[i].second;
  }
  EXPECT_TRUE(runs.back().first);
  EXPECT_EQ(runs.back().second, 1u);
}

TEST(StatusLedTest, StateAtTimeFollowsTheElements) {
  StatusLed led;
  // M = dash (0–359 on), gap 360–479 off, dash 480–839 on, char gap 840–1199 off, C starts 1200
  const std::vector<std::pair<std::uint64_t, bool>> table = {
      {0, true},    {359, true},   {360, false}, {479, false},   {480, true},   {839, true},
      {840, false}, {1199, false}, {1200, true}, {37199, false}, {37200, true}, {37200 * 5 + 1, true}};
  for (const auto& [t, on] : table) EXPECT_EQ(led.on(t), on) << t;
  const auto v = led.view(37200 * 3 + 5);
  EXPECT_EQ(v.cycle_start_ms, 37200u * 3);
  EXPECT_EQ(v.next, nullptr);
}

// §7.5: the fault text is announced by nextText and starts at the next boundary; after the reset
// the normal text returns at the boundary after that.
TEST(StatusLedTest, FaultChangesTheMessageOnlyAtRepetitionBoundaries) {
  core::test::Drive d;
  Leds leds;
  leds.power_up(address_of(d.od));
  const auto step_to = [&](std::uint64_t t) {
    while (d.core.time_ms() < t) {
      d.step();
      leds.update_status(d.core, d.od);
    }
  };
  step_to(10000);
  d.core.inject(core::FaultCause::stroke);  // 7121h, an event cause: raised inside the call
  leds.update_status(d.core, d.od);
  ASSERT_EQ(d.core.state(), core::PdsState::fault);
  const std::string fault_text = "MC+IP192+168+2+150+ERR7121:";
  for (std::uint64_t t : {10000u, 20000u, 37199u}) {
    step_to(t);
    const auto v = leds.green.view(t);
    EXPECT_EQ(v.schedule->text, "MC+IP192+168+2+150:") << t;
    EXPECT_EQ(v.cycle_start_ms, 0u);
    ASSERT_NE(v.next, nullptr) << t;
    EXPECT_EQ(v.next->text, fault_text);
  }
  step_to(37200);
  auto v = leds.green.view(37200);
  EXPECT_EQ(v.schedule->text, fault_text);
  EXPECT_EQ(v.cycle_start_ms, 37200u);
  EXPECT_EQ(v.schedule->cycle_ms, 50880u);
  EXPECT_EQ(v.next, nullptr);
  step_to(40000);
  d.cw(0x80);  // fault reset
  leds.update_status(d.core, d.od);
  ASSERT_EQ(d.core.state(), core::PdsState::switch_on_disabled);
  v = leds.green.view(40000);
  EXPECT_EQ(v.schedule->text, fault_text);
  ASSERT_NE(v.next, nullptr);
  EXPECT_EQ(v.next->text, "MC+IP192+168+2+150:");
  step_to(37200 + 50880 - 1);
  EXPECT_EQ(leds.green.view(d.core.time_ms()).schedule->text, fault_text);
  step_to(37200 + 50880);
  v = leds.green.view(d.core.time_ms());
  EXPECT_EQ(v.schedule->text, "MC+IP192+168+2+150:");
  EXPECT_EQ(v.cycle_start_ms, 37200u + 50880u);
  EXPECT_EQ(v.next, nullptr);
}

// Sampling through a fault and its reset: every repetition decodes to one whole message.
TEST(StatusLedTest, EveryRepetitionStaysValidAcrossStatusChanges) {
  StatusLed led;
  std::vector<bool> samples;
  for (std::uint64_t t = 0; t < 200000; ++t) {
    if (t == 5000) led.set_status(t, 0x7121);
    if (t == 60000) led.set_status(t, std::nullopt);
    if (t == 61000) led.set_status(t, 0x3221);
    if (t == 61500) led.set_status(t, std::nullopt);
    samples.push_back(led.on(t));
  }
  // repetitions: 0 normal, 37200 fault 7121, 88080 normal (status at its start), 125280 normal
  const std::string n = "MC+IP192+168+2+150:";
  EXPECT_EQ(decode_runs(run_lengths(samples), T).substr(0, 3 * n.size() + 27),
            n + "MC+IP192+168+2+150+ERR7121:" + n + n);
}

TEST(StatusLedTest, ChangeAtABoundaryAppliesToTheRepetitionStartingThere) {
  StatusLed led;
  led.set_status(37200, 0x7121);
  EXPECT_EQ(led.view(37200).schedule->text, "MC+IP192+168+2+150+ERR7121:");
  EXPECT_EQ(led.view(37199).schedule->text, "MC+IP192+168+2+150:");
  StatusLed led2;
  led2.set_status(37201, 0x7121);
  EXPECT_EQ(led2.view(37201).schedule->text, "MC+IP192+168+2+150:");
  EXPECT_EQ(led2.view(74400).schedule->text, "MC+IP192+168+2+150+ERR7121:");
}

TEST(StatusLedTest, ShortFaultBetweenBoundariesLeavesNoTrace) {
  StatusLed led;
  led.set_status(1000, 0x7121);
  led.set_status(2000, std::nullopt);
  const auto v = led.view(40000);
  EXPECT_EQ(v.schedule->text, "MC+IP192+168+2+150:");
  EXPECT_EQ(v.cycle_start_ms, 37200u);
}

TEST(StatusLedTest, PowerCycleRestartsAtTimeZeroWithTheNewAddress) {
  StatusLed led;
  led.set_status(5000, 0x7121);
  EXPECT_EQ(led.view(50000).schedule->text, "MC+IP192+168+2+150+ERR7121:");
  led.power_up({10, 0, 0, 1});
  const auto v = led.view(0);
  EXPECT_EQ(v.cycle_start_ms, 0u);
  EXPECT_EQ(v.schedule->text, "MC+IP10+0+0+1:");
  EXPECT_EQ(v.schedule->cycle_ms, 234 * T);
  EXPECT_EQ(v.next, nullptr);
  EXPECT_TRUE(led.on(0));
}

// greenEdges = exactly the changes of on(t), over any window, also before the current repetition.
TEST(StatusLedTest, EdgesMatchTheSampledState) {
  StatusLed led;
  const std::uint64_t now = 100000;
  for (const auto& [from, to] : std::vector<std::pair<std::int64_t, std::int64_t>>{
           {0, 600000}, {-500, 1000}, {37100, 37300}, {99999, 100001}, {500, 500}, {360, 360}}) {
    const auto edges = led.edges(now, from, to);
    std::vector<Edge> expected;
    for (std::int64_t t = std::max<std::int64_t>(from, 0); t <= to; ++t) {
      const auto u = static_cast<std::uint64_t>(t);
      const bool before = u == 0 ? false : led.on(u - 1);
      if (led.on(u) != before) expected.emplace_back(u, led.on(u));
    }
    EXPECT_EQ(edges, expected) << from << ".." << to;
  }
}

}  // namespace
}  // namespace mcemu::led
