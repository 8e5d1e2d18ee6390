// A real drive bundle (tests/support/device_fixture.hpp) behind the pure router, stepped in
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
#include "tests/support/device_fixture.hpp"
#include "trace/trace.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api::testing {

struct ApiFixture {
  explicit ApiFixture(const char* model = "MC349", nlohmann::json config = nlohmann::json::object())
      : bundle(model, std::move(config)),
        preset(bundle.preset()),
        od(bundle.od()),
        core(bundle.core()),
        interpreter(bundle.refgo()),
        ring(bundle.device().trace()) {
    services.info = [this] {
      Info i;
      i.version = "0.1.0";
      i.model = preset.name;
      return i;
    };
    services.trace = &ring;
    bundle.storage().set_auto_complete(true);
    // the UDP notes of the bundle go where the router's go (the server sends both on UDP)
    bundle.on_note = [this](const std::string& text) {
      if (services.note) services.note(text);
    };
  }

  // As the server does: script.kill reaches the engine the API sees (services.script).
  Router& make_router() {
    if (services.script) {
      bundle.device().faults().set_script_kill([this] { return services.script->view().state != "OFF"; },
                                               [this] { services.script->kill(); });
    }
    router = std::make_unique<Router>(bundle.device(), services);
    return *router;
  }
  void release_store_hooks() { bundle.release_store_hooks(); }
  Router& r() {
    if (!router) make_router();
    return *router;
  }
  device::TransportFaults& transport_faults() { return bundle.device().transport_faults(); }
  // The hook the server gives the bundle for a change of the runtime settings (web.md §8.9).
  void observe_settings(std::function<void(const device::RuntimeSettings&)> fn) {
    device::Observers o;
    o.settings_changed = std::move(fn);
    bundle.device().set_observers(std::move(o));
  }

  void step(std::uint64_t n = 1) {
    r();
    bundle.step(n);
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

  mcemu::testing::DeviceFixture bundle;
  const model::ModelPreset& preset;
  od::ObjectDictionary& od;
  core::DriveCore& core;
  refgo::Interpreter& interpreter;
  trace::Ring& ring;
  Services services;
  std::unique_ptr<Router> router;
};

}  // namespace mcemu::web::api::testing
