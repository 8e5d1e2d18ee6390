// A real drive (MC349 dictionary, core, RefGo interpreter) behind the pure router, stepped in
// simulated time, for the web API tests. Services start empty; a test fills what it needs before
// calling make_router().
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "trace/trace.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api::testing {

struct ApiFixture {
  explicit ApiFixture(const char* model = "MC349")
      : preset(*model::find_preset(model)),
        od(preset),
        core(preset, od),
        interpreter(od, core),
        ring(trace::Ring::Clocks{[this] { return core.time_ms(); },
                                 [] { return std::int64_t{1768472102123}; }}) {  // 2026-01-15T10:15:02.123Z
    core.power_on();
    services.info = [this] {
      Info i;
      i.version = "0.1.0";
      i.model = preset.name;
      return i;
    };
    services.trace = &ring;
  }

  Router& make_router() {
    router = std::make_unique<Router>(Drive{od, core, interpreter, preset}, services);
    return *router;
  }
  Router& r() {
    if (!router) make_router();
    return *router;
  }

  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      core.step();
      interpreter.on_step();
      r().on_step();
    }
  }

  // One request; checks that respond is called exactly once before handle() returns.
  Response call(std::string method, std::string target, std::string body = "", std::string type = "") {
    if (type.empty() && method == "POST") type = "application/json";
    Response out;
    int calls = 0;
    r().handle(make_request(std::move(method), std::move(target), std::move(type), std::move(body)),
               [&](Response resp) {
                 out = std::move(resp);
                 ++calls;
               });
    EXPECT_EQ(calls, 1);
    return out;
  }
  nlohmann::json json_of(const Response& resp) { return nlohmann::json::parse(resp.body); }
  nlohmann::json get(const std::string& target) { return json_of(call("GET", target)); }
  nlohmann::json status() { return get("/api/v1/status"); }
  std::int64_t n(std::uint16_t i, std::uint8_t s) { return *od.read_number(i, s); }
  nlohmann::json refgo(const std::string& line) {
    return json_of(call("POST", "/api/v1/refgo", nlohmann::json{{"line", line}}.dump()));
  }
  // The api-channel trace texts recorded so far.
  std::vector<std::string> api_events() {
    trace::Ring::Query q;
    q.channels = trace::ChannelSet::none();
    q.channels.add(trace::Channel::api);
    q.limit = 10000;
    std::vector<std::string> out;
    for (const auto& e : ring.query(q).events) out.push_back(e.text);
    return out;
  }

  model::ModelPreset preset;
  od::ObjectDictionary od;
  core::DriveCore core;
  refgo::Interpreter interpreter;
  trace::Ring ring;
  Services services;
  std::unique_ptr<Router> router;
};

}  // namespace mcemu::web::api::testing
