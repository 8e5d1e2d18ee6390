// Fuzz target: HTTP requests through the pure router (web.md §1.3, §1.4, §7–§9) on the real drive —
// dictionary, core, I/O functions, RefGo interpreter, Store/Restore, fault injections, scope, trace,
// LEDs — in drive time, built fresh for every input so that a crash reproduces from its input
// alone. Beast's parser (web/net) is not under test; what it hands the router is:
// any method, any target bytes, any headers, any body.
//
// Input: records [op][payload]; ops send a request to a route of the router's own table (its
// {parameters} and query filled from the input) or to raw target bytes, with a chosen method,
// content type and Origin and a fuzzed body; advance drive time by 1–256 ms; complete or fail
// pending state-file writes.
// Drive time advances as under the server's manual clock, also for POST /api/v1/clock/advance
// (tests/fuzz/drive_time.hpp: quiet stretches skipped, needed steps in full; every other op
// touches the drive as a client's request wakes the clock). Budget per input (drive_time.hpp): 20 s
// of drive time, 3 s of it in full steps: fault-injection durations and LED schedules run out, a
// move or timed jog started over the API runs 3 s; an idle drive passes it in a few full steps.
// Oracles beyond "no crash, no sanitizer report": every request is answered exactly once (a Store
// answers when its write completes), the status is 1xx–5xx, a JSON answer parses, a POST to /api/
// without a JSON content type is refused (415, or 404/405 first) before it acts (web.md §1.3), and the dictionary is
// never corrupted.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "drive/led/leds.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "tests/fuzz/drive_bundle.hpp"
#include "tests/fuzz/drive_time.hpp"
#include "tests/support/device_fixture.hpp"
#include "trace/trace.hpp"
#include "web/api/led_view.hpp"
#include "web/api/router.hpp"

namespace {

using namespace mcemu;
using web::api::Request;
using web::api::Response;

constexpr std::array<const char*, 8> k_methods = {"GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS", "get"};
constexpr std::array<const char*, 5> k_types = {"application/json", "", "text/plain", "application/json; charset=utf-8",
                                                "multipart/form-data; boundary=x"};
constexpr std::array<const char*, 4> k_origins = {"", "http://127.0.0.1:8080", "http://attacker.example", "null"};
constexpr std::array<const char*, 8> k_params = {"6041", "6083h", "0", "1", "f1", "FFFF", "", "x%00"};

// The router's own table (a static of the code, the same for every input).
std::vector<web::api::RouteDoc> g_routes;

std::string fill_route(std::string_view pattern, fuzz::Records& r) {
  std::string out;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '{') {
      out.push_back(pattern[i]);
      continue;
    }
    const auto close = pattern.find('}', i);
    i = close == std::string_view::npos ? pattern.size() : close;
    if (r.byte() & 1) {
      out += k_params[r.byte() % k_params.size()];
    } else {
      out += r.bytes();
    }
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  g_routes = web::api::Router::route_docs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  testing::DeviceOptions options;
  options.keep_events = false;
  testing::DeviceFixture drive("MC349", std::move(options));
  auto& dev = drive.device();

  web::api::Services services;
  services.info = [&] {
    web::api::Info i;
    i.version = "fuzz";
    i.model = dev.preset().name;
    return i;
  };
  services.trace = &dev.trace();
  services.led_state = [&] {
    const auto t = dev.core().time_ms();
    return web::api::LedStatus{dev.leds().green.on(t), dev.leds().yellow.on(t)};
  };
  services.led = [&](std::string_view query) {
    return web::api::led_response(dev.leds(), dev.core().time_ms(), query);
  };
  services.clock = [] { return web::api::ClockInfo{"manual", 0}; };
  fuzz::DriveTime drive_time(dev.steps());
  services.advance_clock = [&](std::uint64_t ms, std::function<void(std::uint64_t)> done) {
    drive_time.touch();  // the server runs the steps after the request's wake
    drive_time.advance(ms);
    done(dev.core().time_ms());
  };
  services.power_cycle = [&](std::function<void()> done) {
    dev.power_cycle();
    done();
  };
  services.note = [](const std::string&) {};
  web::api::Router router(dev, std::move(services));

  std::uint64_t asked = 0;
  std::uint64_t answered = 0;
  fuzz::Records r(data, size);
  while (!r.empty()) {
    const std::uint8_t op = r.byte();
    switch (op % 5) {
      case 0:
      case 1: {
        Request req;
        req.method = k_methods[r.byte() % k_methods.size()];
        if (op % 5 == 0) {
          const auto& route = g_routes[r.u16() % g_routes.size()];
          req.target = fill_route(route.path, r);
          if (r.byte() & 1) {
            req.target += '?';
            req.target += r.bytes();
          }
        } else {
          req.target = std::string(r.bytes());
        }
        req.content_type = k_types[r.byte() % k_types.size()];
        const std::string origin = k_origins[r.byte() % k_origins.size()];
        if (!origin.empty()) req.headers.emplace_back("origin", origin);
        req.headers.emplace_back("host", "127.0.0.1:8080");
        req.body = std::string(r.bytes());
        req.conn = 1 + r.byte() % 4;
        req.peer = "127.0.0.1:40000";
        // web.md §1.3: what a page of another site can send without a CORS preflight — a POST with a
        // "simple" content type — must not act (415); JSON bodies need a preflight, which fails.
        const bool simple_post = req.method == "POST" && req.content_type.rfind("application/json", 0) != 0 &&
                                 req.target.rfind("/api/", 0) == 0;
        ++asked;
        auto once = std::make_shared<bool>(false);  // the answer may come after this block (a Store)
        router.handle(req, [&answered, once, simple_post, method = req.method](Response resp) {
          if (*once) fuzz::fail("a request answered twice");
          *once = true;
          // refused before any handler runs (a snapshot compare per request made this target 40x slower)
          if (simple_post && resp.status < 400) {
            fuzz::fail("a POST without a JSON body got " + std::to_string(resp.status));
          }
          ++answered;
          if (resp.status < 100 || resp.status > 599) fuzz::fail("status " + std::to_string(resp.status));
          if (method != "HEAD" && resp.content_type.rfind("application/json", 0) == 0 && !resp.body.empty() &&
              !nlohmann::json::accept(resp.body)) {  // validates without building the document
            fuzz::fail("answer is not JSON: " + resp.body.substr(0, 200));
          }
        });
        break;
      }
      case 2: drive_time.advance(r.byte() + 1u); break;
      case 3: drive.storage().complete(true); break;
      default: drive.storage().complete(false); break;
    }
    if (op % 5 != 2) drive_time.touch();  // the server's wake after a client's request
  }
  while (drive.storage().pending() > 0) drive.storage().complete(true);
  if (answered != asked) {
    fuzz::fail("answered " + std::to_string(answered) + " of " + std::to_string(asked) + " requests");
  }
  fuzz::check_dictionary(dev.od());
  return 0;
}
