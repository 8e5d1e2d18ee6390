// The yellow LINK/ACT LED (morse-led.md §5, §7 item 6): steady with counted connections, 40 ms
// activity flicker, ignored while showing and for 40 ms after, last 64 edges, power cycle.
#include "drive/led/link_led.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace mcemu::led {
namespace {

using Edges = std::vector<LinkLed::Edge>;

TEST(LinkLedTest, OffWithoutClientOnWhileConnected) {
  LinkLed led;
  EXPECT_FALSE(led.on(0));
  led.connection_opened(100);
  EXPECT_TRUE(led.on(100));
  led.connection_opened(200);
  led.connection_closed(300);
  EXPECT_TRUE(led.on(300));
  EXPECT_EQ(led.connections(), 1u);
  led.connection_closed(400);
  EXPECT_FALSE(led.on(400));
  led.connection_closed(500);  // none open: ignored
  EXPECT_EQ(led.connections(), 0u);
  EXPECT_EQ(led.edges(1000), (Edges{{100, true}, {400, false}}));
}

// §7.6: traffic every 10 ms on a connected link shows 40 ms flickers whose starts are 80 ms apart.
TEST(LinkLedTest, TrafficEvery10MsFlickersAt12_5Hz) {
  LinkLed led;
  led.connection_opened(1000);
  for (std::uint64_t t = 1000; t <= 2000; t += 10) led.activity(t);
  const Edges e = led.edges(2100);
  ASSERT_GE(e.size(), 4u);
  // the activity at the connect time inverts at once: "on" at 1000 lasts no time and is no edge
  EXPECT_EQ(e.front(), (LinkLed::Edge{1040, true}));
  std::vector<std::uint64_t> offs;
  std::vector<std::uint64_t> ons;
  for (std::size_t i = 0; i < e.size(); ++i) (e[i].second ? ons : offs).push_back(e[i].first);
  for (std::size_t i = 1; i < e.size(); ++i) EXPECT_NE(e[i].second, e[i - 1].second);
  for (std::size_t i = 0; i < offs.size(); ++i) {
    EXPECT_EQ(offs[i], 1080 + 80 * i) << i;
  }
  for (std::size_t i = 0; i < offs.size(); ++i) {
    // each off lasts exactly 40 ms
    const auto it = std::find(ons.begin(), ons.end(), offs[i] + 40);
    EXPECT_NE(it, ons.end()) << offs[i];
  }
}

struct Step {
  char what;  // o = opened, c = closed, a = activity
  std::uint64_t t;
};
struct FlickerCase {
  const char* name;
  std::vector<Step> steps;
  std::uint64_t at;
  Edges edges;
};

class FlickerTest : public ::testing::TestWithParam<FlickerCase> {};

TEST_P(FlickerTest, Edges) {
  LinkLed led;
  for (const Step& s : GetParam().steps) {
    if (s.what == 'o') led.connection_opened(s.t);
    if (s.what == 'c') led.connection_closed(s.t);
    if (s.what == 'a') led.activity(s.t);
  }
  EXPECT_EQ(led.edges(GetParam().at), GetParam().edges);
}

INSTANTIATE_TEST_SUITE_P(
    Rules, FlickerTest,
    ::testing::Values(
        FlickerCase{"idle_activity_lights_40ms", {{'a', 10}}, 100, {{10, true}, {50, false}}},
        FlickerCase{
            "connected_activity_darkens_40ms", {{'o', 0}, {'a', 10}}, 100, {{0, true}, {10, false}, {50, true}}},
        FlickerCase{"ignored_while_showing", {{'a', 10}, {'a', 49}}, 200, {{10, true}, {50, false}}},
        FlickerCase{"ignored_for_40ms_after", {{'a', 10}, {'a', 89}}, 200, {{10, true}, {50, false}}},
        FlickerCase{
            "next_flicker_at_80ms", {{'a', 10}, {'a', 90}}, 200, {{10, true}, {50, false}, {90, true}, {130, false}}},
        FlickerCase{"end_not_reported_before_it_happens", {{'a', 10}}, 49, {{10, true}}},
        FlickerCase{"connect_during_flicker_keeps_it_inverted",
                    {{'a', 10}, {'o', 20}},
                    100,
                    {{10, true}, {20, false}, {50, true}}},
        FlickerCase{"close_during_flicker",
                    {{'o', 0}, {'a', 10}, {'c', 20}},
                    100,
                    {{0, true}, {10, false}, {20, true}, {50, false}}},
        FlickerCase{"same_time_changes_are_no_edge", {{'o', 0}, {'a', 0}}, 100, {{40, true}}},
        FlickerCase{
            "activity_at_flicker_end_is_in_the_quiet_time", {{'a', 10}, {'a', 50}}, 200, {{10, true}, {50, false}}}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(LinkLedTest, KeepsTheLast64Edges) {
  LinkLed led;
  for (std::uint64_t k = 0; k < 100; ++k) led.activity(k * 80);
  const Edges e = led.edges(100 * 80);
  ASSERT_EQ(e.size(), 64u);
  EXPECT_EQ(e.back(), (LinkLed::Edge{99 * 80 + 40, false}));
  EXPECT_EQ(e.front(), (LinkLed::Edge{68 * 80, true}));
}

TEST(LinkLedTest, PowerCycleForgetsEdgesKeepsConnections) {
  LinkLed led;
  led.connection_opened(10);
  led.activity(5000);
  led.power_up();
  EXPECT_TRUE(led.on(0));
  EXPECT_TRUE(led.edges(10).empty());
  led.activity(20);
  EXPECT_EQ(led.edges(100), (Edges{{20, false}, {60, true}}));
}

}  // namespace
}  // namespace mcemu::led
