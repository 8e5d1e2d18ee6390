// GET and DELETE /api/v1/lint (docs/lint.md §5) on a real bundle: the counts and recent findings of
// what a master did over the API, the reset, the mode in /api/v1/info and the OpenAPI rows.
#include <gtest/gtest.h>

#include "tests/web/api_fixture.hpp"

namespace mcemu::web::api::testing {
namespace {

using json = nlohmann::json;

const json* rule(const json& body, const std::string& id) {
  for (const auto& r : body["rules"]) {
    if (r["id"] == id) return &r;
  }
  return nullptr;
}

TEST(LintApi, FindingsCountsAndReset) {
  ApiFixture f;
  f.step(10);  // Switch on disabled
  EXPECT_EQ(f.get("/api/v1/lint")["totals"]["warn"], 0);
  // Enable operation straight from Switch on disabled: the drive ignores it
  ASSERT_EQ(f.call("PUT", "/api/v1/objects/6040/0", R"({"value": 15})", "application/json").status, 200);
  const auto r = f.call("GET", "/api/v1/lint");
  EXPECT_EQ(r.status, 200);
  const json body = f.json_of(r);
  EXPECT_EQ(body["mode"], "warn");
  EXPECT_EQ(body["totals"]["warn"], 1);
  const json* ignored = rule(body, "cia402.command_ignored");
  ASSERT_NE(ignored, nullptr);
  EXPECT_EQ((*ignored)["count"], 1);
  EXPECT_NE((*ignored)["reference"].get<std::string>().find("drive-core.md §4.2"), std::string::npos);
  ASSERT_EQ(body["recent"].size(), 1U);
  EXPECT_EQ(body["recent"][0]["origin"], "web");
  EXPECT_EQ(body["recent"][0]["detail"], "controlword 0x000F (Enable operation) in Switch on disabled is ignored");
  const auto cleared = f.call("DELETE", "/api/v1/lint");
  EXPECT_EQ(cleared.status, 200);
  EXPECT_EQ(f.json_of(cleared)["totals"]["warn"], 0);
  EXPECT_TRUE(f.get("/api/v1/lint")["recent"].empty());
  // the reset is journaled like every emulator write (trace channel api)
  trace::Ring::Query q;
  q.channels = trace::ChannelSet::none();
  q.channels.add(trace::Channel::api);
  const auto events = f.ring.query(q).events;
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().text, "lint reset");
}

TEST(LintApi, InfoNamesTheModeAndOpenApiTheRows) {
  ApiFixture f("MC349", json{{"lint", {{"mode", "strict"}, {"timing", false}}}});
  const json info = f.get("/api/v1/info");
  EXPECT_EQ(info["lint"], json::parse(R"({"mode": "strict", "timing": false})"));
  EXPECT_EQ(f.get("/api/v1/lint")["mode"], "strict");
  const json doc = f.get("/api/v1/openapi.json");
  EXPECT_FALSE(doc["paths"]["/api/v1/lint"]["get"].contains("security"));
  EXPECT_TRUE(doc["paths"]["/api/v1/lint"]["delete"].contains("security"));
  EXPECT_EQ(f.call("POST", "/api/v1/lint", "{}").status, 405);
}

}  // namespace
}  // namespace mcemu::web::api::testing
