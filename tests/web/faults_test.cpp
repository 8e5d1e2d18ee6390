// Fault injection over the JSON API (web.md §9) acting on a real drive core in virtual time.
#include "web/api/faults.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

struct Fixture {
  Fixture() : preset(*model::find_preset("MC349")), od(preset), core(preset, od), faults(core) {
    core.power_on();
    step(10);
  }
  void step(int n) {
    for (int i = 0; i < n; ++i) {
      core.step();
      faults.on_step();
    }
  }
  json body(const Response& r) { return json::parse(r.body); }
  std::int64_t n(std::uint16_t i, std::uint8_t s) { return *od.read_number(i, s); }
  std::vector<core::Emcy> emcys() {
    std::vector<core::Emcy> out;
    for (const auto& e : core.drain_events()) {
      if (const auto* m = std::get_if<core::Emcy>(&e)) out.push_back(*m);
    }
    return out;
  }

  model::ModelPreset preset;
  od::ObjectDictionary od;
  core::DriveCore core;
  FaultInjections faults;
};

TEST(FaultInjection, InjectCauseListAndRemove) {
  Fixture f;
  f.emcys();
  auto r = f.faults.create(R"({"kind": "drive.inject", "cause": "under_voltage"})");
  ASSERT_EQ(r.status, 201) << r.body;
  const std::string id = f.body(r)["id"];
  EXPECT_EQ(id, "f1");
  f.step(5);
  EXPECT_EQ(f.n(0x6041, 0) & 0x000F, 0x0008) << "fault";
  EXPECT_EQ(f.n(0x603F, 0), 0x3221);
  const auto emcys = f.emcys();
  ASSERT_FALSE(emcys.empty());
  EXPECT_EQ(emcys.front().code, 0x3221);
  EXPECT_EQ(f.body(f.faults.list())["faults"].size(), 1u);
  EXPECT_EQ(f.faults.remove(id).status, 200);
  EXPECT_EQ(f.faults.remove(id).status, 404);
  EXPECT_EQ(f.faults.active(), 0u);
  // the cause is gone, so a fault reset now succeeds
  f.od.write(0x6040, 0, od::Value{std::int64_t{0x80}}, od::Origin::web);
  f.step(20);
  EXPECT_EQ(f.n(0x6041, 0) & 0x004F, 0x0040) << "switch on disabled after the reset";
}

TEST(FaultInjection, DurationIsDriveTime) {
  Fixture f;
  ASSERT_EQ(f.faults.create(R"({"kind": "drive.load", "value": 0.1, "durationMs": 50})").status, 201);
  f.step(49);
  EXPECT_EQ(f.faults.active(), 1u);
  f.step(1);
  EXPECT_EQ(f.faults.active(), 0u);
}

TEST(FaultInjection, EmcyByCodeIsOneShot) {
  Fixture f;
  f.emcys();
  ASSERT_EQ(f.faults.create(R"({"kind": "drive.emcy", "code": "4210h"})").status, 201);
  f.step(3);
  EXPECT_EQ(f.n(0x603F, 0), 0x4210);
  EXPECT_EQ(f.faults.active(), 0u) << "removed itself after one step";
  EXPECT_EQ(f.faults.create(R"({"kind": "drive.emcy", "code": "1234h"})").status, 400) << "no fault has 1234h";
}

TEST(FaultInjection, EnvironmentKindsAndObstacle) {
  Fixture f;
  EXPECT_EQ(f.faults.create(R"({"kind": "drive.supply", "volts": 30})").status, 201);
  EXPECT_EQ(f.faults.create(R"({"kind": "drive.ambient", "celsius": 40})").status, 201);
  EXPECT_EQ(f.faults.create(R"({"kind": "drive.obstacle", "positionInc": 1000, "side": 1})").status, 201);
  EXPECT_EQ(f.body(f.faults.list())["faults"].size(), 3u);
  EXPECT_EQ(f.faults.remove_all().status, 200);
  EXPECT_EQ(f.faults.active(), 0u);
}

TEST(FaultInjection, BadRequestsAre400) {
  Fixture f;
  for (const char* bad : {"{", R"({"cause": "stroke"})", R"({"kind": "drive.inject"})",
                          R"({"kind": "drive.inject", "cause": "gremlins"})", R"({"kind": "drive.supply"})",
                          R"({"kind": "drive.obstacle", "positionInc": 5, "side": 2})",
                          R"({"kind": "drive.load", "value": 1, "durationMs": 0})",
                          R"({"kind": "drive.load", "value": 1, "count": 2})", R"({"kind": "refgo.noReply"})"}) {
    EXPECT_EQ(f.faults.create(bad).status, 400) << bad;
  }
  EXPECT_EQ(f.faults.active(), 0u) << "a refused request injects nothing";
}

TEST(FaultInjection, RoutedByTheRouter) {
  Fixture f;
  Router router(
      f.od, [] { return Info{}; }, {}, &f.faults);
  Response out;
  router.handle(Request{"POST", "/api/v1/faults", "application/json", R"({"kind": "drive.load", "value": 0.01})"},
                [&](Response r) { out = std::move(r); });
  EXPECT_EQ(out.status, 201);
  router.handle(Request{"DELETE", "/api/v1/faults/f1", "", ""}, [&](Response r) { out = std::move(r); });
  EXPECT_EQ(out.status, 200);
  router.handle(Request{"PUT", "/api/v1/faults", "", ""}, [&](Response r) { out = std::move(r); });
  EXPECT_EQ(out.status, 405);
}

}  // namespace
}  // namespace mcemu::web::api
