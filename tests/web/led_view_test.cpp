// The LED JSON of morse-led.md §6.1 and §6.2 (GET /api/v1/led with the optional window).
#include "web/api/led_view.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/drive/led/morse_decoder.hpp"

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

TEST(LedViewTest, StatusSnapshotMember) {
  led::Leds leds;
  EXPECT_EQ(led_state_json(leds, 0), (json{{"green", true}, {"yellow", false}}));
  leds.yellow.connection_opened(100);
  EXPECT_EQ(led_state_json(leds, 400), (json{{"green", false}, {"yellow", true}}));
}

TEST(LedViewTest, ScheduleDocumentDecodesToItsText) {
  led::Leds leds;
  leds.yellow.activity(123001);
  const Response r = led_response(leds, 123456, "");
  ASSERT_EQ(r.status, 200);
  const json j = json::parse(r.body);
  EXPECT_EQ(j["timeMs"], 123456);
  const json& g = j["green"];
  EXPECT_EQ(g["text"], "MC+IP192+168+2+150:");
  EXPECT_EQ(g["unitMs"], 120);
  EXPECT_EQ(g["cycleStartMs"], 111600);
  EXPECT_EQ(g["cycleMs"], 37200);
  EXPECT_TRUE(g["nextText"].is_null());
  const auto elements = g["elements"].get<std::vector<std::uint32_t>>();
  EXPECT_EQ(led::test::decode_elements(elements, 120), "MC+IP192+168+2+150:");
  std::uint64_t on = 0;
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    sum += elements[i];
    if (i % 2 == 0) on += elements[i];
  }
  EXPECT_EQ(sum, 37200u);
  EXPECT_EQ(on, 22080u);
  EXPECT_EQ(g["on"], leds.green.on(123456));
  EXPECT_EQ(j["yellow"], (json{{"on", false}, {"connections", 0}, {"edges", {{123001, true}, {123041, false}}}}));
  EXPECT_FALSE(j.contains("greenEdges"));
}

TEST(LedViewTest, NextTextAnnouncesTheFaultMessage) {
  led::Leds leds;
  leds.green.set_status(1000, 0x7121);
  const json j = json::parse(led_response(leds, 2000, "").body);
  EXPECT_EQ(j["green"]["text"], "MC+IP192+168+2+150:");
  EXPECT_EQ(j["green"]["nextText"], "MC+IP192+168+2+150+ERR7121:");
}

TEST(LedViewTest, WindowAddsGreenEdges) {
  led::Leds leds;
  const json j = json::parse(led_response(leds, 0, "fromMs=0&toMs=1200").body);
  EXPECT_EQ(j["greenEdges"], (json{{0, true}, {360, false}, {480, true}, {840, false}, {1200, true}}));
  const json k = json::parse(led_response(leds, 0, "x=1&toMs=600000&fromMs=0").body);
  EXPECT_FALSE(k["greenEdges"].empty());
}

struct BadQuery {
  const char* query;
};
class LedViewBadQuery : public ::testing::TestWithParam<BadQuery> {};

TEST_P(LedViewBadQuery, Is400Syntax) {
  led::Leds leds;
  const Response r = led_response(leds, 0, GetParam().query);
  EXPECT_EQ(r.status, 400);
  const json j = json::parse(r.body);
  EXPECT_EQ(j["error"]["code"], "syntax");
  EXPECT_TRUE(j["error"]["message"].is_string());
}

INSTANTIATE_TEST_SUITE_P(Queries, LedViewBadQuery,
                         ::testing::Values(BadQuery{"fromMs=5"}, BadQuery{"toMs=5"}, BadQuery{"fromMs=a&toMs=5"},
                                           BadQuery{"fromMs=10&toMs=9"}, BadQuery{"fromMs=0&toMs=600001"},
                                           BadQuery{"fromMs=&toMs=5"}, BadQuery{"fromMs=1.5&toMs=5"},
                                           BadQuery{"fromMs=-9223372036854775808&toMs=9223372036854775807"}));

TEST(LedViewTest, WindowLimitsAreInclusive) {
  led::Leds leds;
  EXPECT_EQ(led_response(leds, 0, "fromMs=100&toMs=600100").status, 200);
  EXPECT_EQ(led_response(leds, 0, "fromMs=7&toMs=7").status, 200);
  EXPECT_EQ(led_response(leds, 0, "fromMs=-10&toMs=100").status, 200);
}

}  // namespace
}  // namespace mcemu::web::api
