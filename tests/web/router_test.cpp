// The pure HTTP router (web.md §1.3, §1.4, §7, §8): dispatch by the route table, 404/405/415,
// query checking, every endpoint of §8 with the services it uses, the journal of API writes.
#include "web/api/router.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tuple>

#include "tests/web/api_fixture.hpp"
#include "web/api/http_util.hpp"
#include "web/api/led_view.hpp"
#include "web/assets/assets.hpp"

namespace mcemu::web::api {
namespace {

using device::apply_settings;
using device::relaxation;
using device::RuntimeSettings;
using device::settings_json;

using json = nlohmann::json;
using testing::ApiFixture;

std::string header(const Response& r, std::string_view name) {
  for (const auto& h : r.headers) {
    if (h.first == name) return h.second;
  }
  return {};
}

// ---- path patterns (routes.hpp) ------------------------------------------------------------------

TEST(Routes, PathPatternsMatchSegmentBySegment) {
  struct Row {
    std::string_view pattern, path;
    std::optional<std::vector<std::string>> values;
  };
  using V = std::vector<std::string>;
  const Row rows[] = {
      {"/api/v1/status", "/api/v1/status", V{}},
      {"/api/v1/status", "/api/v1/statu", std::nullopt},
      {"/api/v1/status", "/api/v1/status/", std::nullopt},  // one more (empty) segment
      {"/api/v1/status", "/api/v1", std::nullopt},
      {"/api/v1/objects/{index}/{sub}", "/api/v1/objects/6041/0", V{"6041", "0"}},
      {"/api/v1/objects/{index}/{sub}", "/api/v1/objects/6041", std::nullopt},
      {"/api/v1/objects/{index}/{sub}", "/api/v1/objects/6041/0/1", std::nullopt},
      {"/api/v1/objects/{index}", "/api/v1/objects/", V{""}},  // a parameter matches an empty segment
      {"/api/v1/faults/{id}", "/api/v2/faults/f7", std::nullopt},
      {"/api/v1/status", "api/v1/status", std::nullopt},  // not a path
      {"/api/v1/status", "", std::nullopt},
      {"", "/api/v1/status", std::nullopt},
  };
  for (const auto& r : rows) {
    EXPECT_EQ(match_path(r.pattern, r.path), r.values) << r.pattern << " vs " << r.path;
    EXPECT_EQ(path_matches(r.pattern, r.path), r.values.has_value()) << r.pattern << " vs " << r.path;
  }
  EXPECT_EQ(parameter_count("/api/v1/objects/{index}/{sub}"), 2U);
  EXPECT_EQ(parameter_count("/api/v1/status"), 0U);
  EXPECT_EQ(parameter_count("/api/v1/faults/{id}"), 1U);
  EXPECT_EQ(parameter_count(""), 0U);
  EXPECT_EQ(parameter_names("/api/v1/objects/{index}/{sub}"), (std::vector<std::string>{"index", "sub"}));
}

// ---- dispatch ---------------------------------------------------------------------------------

TEST(Router, UnknownPathsGetThe404Page) {
  ApiFixture f;
  for (const char* p : {"/nothing", "/static/none.js", "/apix/v1/info", "/api"}) {
    const auto r = f.call("GET", p);
    EXPECT_EQ(r.status, 404) << p;
    EXPECT_EQ(r.content_type, "text/html; charset=utf-8") << p;
    EXPECT_NE(r.body.find("/index.html"), std::string::npos) << p;
  }
}

// web.md §1.4: an API client parses JSON, so an unknown path under /api/ is a JSON 404.
TEST(Router, UnknownApiPathsGetAJson404) {
  ApiFixture f;
  for (const char* p :
       {"/api/v1/nothing", "/api/v2/info", "/api/v1/objects/6041", "/api/v1/info/x", "/api/", "/api/v1/nothing?x=1"}) {
    for (const char* method : {"GET", "POST", "PUT", "DELETE"}) {
      const auto r = f.call(method, p, "{}", "application/json");
      EXPECT_EQ(r.status, 404) << method << " " << p;
      EXPECT_EQ(r.content_type, "application/json") << method << " " << p;
      EXPECT_EQ(header(r, "Cache-Control"), "no-store") << p;
      const auto body = f.json_of(r);
      EXPECT_EQ(body["error"]["code"], "not-found") << p;
      EXPECT_EQ(body["error"]["message"].get<std::string>().rfind("no API route /api/", 0), 0u) << body.dump();
    }
  }
}

TEST(Router, WrongMethodIs405WithAllowFromTheTable) {
  ApiFixture f;
  struct Case {
    const char* method;
    const char* path;
    const char* allow;
  };
  for (const auto& c :
       {Case{"DELETE", "/api/v1/info", "GET, HEAD"}, Case{"PUT", "/api/v1/faults", "GET, HEAD, POST, DELETE"},
        Case{"POST", "/api/v1/objects/6041/0", "GET, HEAD, PUT"}, Case{"GET", "/api/v1/objects/read", "POST"},
        Case{"GET", "/api/v1/faults/f1", "DELETE"}, Case{"OPTIONS", "/api/v1/status", "GET, HEAD"},
        Case{"PATCH", "/api/v1/settings", "GET, HEAD, PUT"}, Case{"HEAD", "/api/v1/store", "POST"}}) {
    const auto r = f.call(c.method, c.path, "", "application/json");
    EXPECT_EQ(r.status, 405) << c.method << " " << c.path;
    EXPECT_EQ(header(r, "Allow"), c.allow) << c.method << " " << c.path;
    EXPECT_EQ(f.json_of(r)["error"]["code"], "method");
  }
}

TEST(Router, PostNeedsTheJsonMediaType) {
  ApiFixture f;
  for (const char* type : {"application/json", "Application/JSON", "application/json; charset=utf-8",
                           "  application/json ;charset=UTF-8"}) {
    EXPECT_EQ(f.call("POST", "/api/v1/objects/read", R"({"objects": []})", type).status, 200) << type;
  }
  for (const char* type : {"text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x",
                           "application/jsonx", "application/json-patch+json", "json", " "}) {
    const auto r = f.call("POST", "/api/v1/objects/read", R"({"objects": []})", type);
    EXPECT_EQ(r.status, 415) << type;
    EXPECT_EQ(f.json_of(r)["error"]["code"], "content-type");
  }
  // an empty body of a JSON POST counts as {}
  EXPECT_EQ(f.call("POST", "/api/v1/store", "", "application/json").status, 200) << "not a 400: {} is a valid body";
  EXPECT_EQ(f.api_events().back(), "store ok");
  EXPECT_EQ(f.call("POST", "/api/v1/objects/read", "", "application/json").status, 400) << "{} has no objects";
}

TEST(Router, NoCorsHeadersEver) {
  ApiFixture f;
  for (const char* p : {"/api/v1/info", "/api/v1/status", "/nothing", "/api/v1/openapi.json"}) {
    const auto r = f.call("GET", p);
    for (const auto& h : r.headers) EXPECT_NE(h.first.rfind("Access-Control", 0), 0u) << p << " " << h.first;
  }
  const auto r = f.call("OPTIONS", "/api/v1/faults");
  EXPECT_EQ(r.status, 405) << "a CORS preflight is never answered positively";
}

TEST(Router, HeadIsAGet) {
  ApiFixture f;
  const auto get = f.call("GET", "/api/v1/info");
  const auto head = f.call("HEAD", "/api/v1/info");
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.content_type, get.content_type);
}

TEST(Router, UnknownOrMalformedQueryIs400) {
  ApiFixture f;
  EXPECT_EQ(f.call("GET", "/api/v1/info?x=1").status, 400);
  EXPECT_EQ(f.call("GET", "/api/v1/status?%").status, 400);
  EXPECT_EQ(f.call("GET", "/api/v1/info?").status, 200);
}

TEST(Router, ApiAnswersAreJsonAndNotCached) {
  ApiFixture f;
  const auto r = f.call("GET", "/api/v1/info");
  EXPECT_EQ(r.content_type, "application/json");
  EXPECT_EQ(header(r, "Cache-Control"), "no-store");
}

TEST(Router, PagesGoToThePagesHook) {
  ApiFixture f;
  std::vector<std::string> seen;
  f.services.pages = [&](const Request& r, const Respond& respond) {
    seen.push_back(r.method + " " + r.target);
    if (r.target != "/") return false;
    Response page;
    page.content_type = "text/html; charset=utf-8";
    page.body = "start page";
    respond(page);
    return true;
  };
  f.make_router();
  EXPECT_EQ(f.call("GET", "/").body, "start page");
  EXPECT_EQ(f.call("GET", "/missing.html").status, 404);
  EXPECT_EQ(f.call("POST", "/program.html", "x", "multipart/form-data").status, 503)
      << "no 415 outside /api/; /program.html is the router's own (web.md §6), here without an engine";
  EXPECT_EQ(seen, (std::vector<std::string>{"GET /", "GET /missing.html"}));
}

// ---- OpenAPI: every route is described and every described route exists ----------------------

std::string sample_path(std::string path) {
  for (const auto& [param, value] : {std::pair{"{index}", "6041"}, {"{sub}", "0"}, {"{id}", "f1"}}) {
    const auto at = path.find(param);
    if (at != std::string::npos) path.replace(at, std::string(param).size(), value);
  }
  return path;
}

TEST(OpenApi, EveryRouteIsDescribedAndEveryDescribedRouteExists) {
  ApiFixture f;
  const auto doc_response = f.call("GET", "/api/v1/openapi.json");
  ASSERT_EQ(doc_response.status, 200);
  const json doc = f.json_of(doc_response);
  EXPECT_EQ(doc["openapi"], "3.0.3");
  EXPECT_EQ(doc["info"]["version"], "0.1.0");
  // every row of the table is in the document
  const auto rows = Router::route_docs();
  for (const auto& r : rows) {
    std::string m(to_string(r.method));
    std::transform(m.begin(), m.end(), m.begin(), [](char c) { return static_cast<char>(std::tolower(c)); });
    ASSERT_TRUE(doc["paths"].contains(std::string(r.path))) << r.path;
    EXPECT_TRUE(doc["paths"][std::string(r.path)].contains(m)) << m << " " << r.path;
    EXPECT_FALSE(doc["paths"][std::string(r.path)][m]["summary"].get<std::string>().empty()) << r.path;
  }
  // every operation of the document is served: neither the 404 page nor 405
  std::size_t operations = 0;
  for (const auto& [path, methods] : doc["paths"].items()) {
    for (const auto& [method, op] : methods.items()) {
      ++operations;
      std::string upper = method;
      for (auto& c : upper) c = static_cast<char>(std::toupper(c));
      const auto r = f.call(upper, sample_path(path), "{}", "application/json");
      EXPECT_NE(r.status, 405) << upper << " " << path;
      EXPECT_FALSE(r.status == 404 && r.content_type.rfind("text/html", 0) == 0) << upper << " " << path;
      EXPECT_EQ(r.body.find("no API route"), std::string::npos) << upper << " " << path;
      for (const auto& p : op.value("parameters", json::array())) {
        EXPECT_TRUE(p["in"] == "path" || p["in"] == "query") << path;
      }
    }
  }
  EXPECT_EQ(operations, rows.size());
  // the request bodies are valid JSON Schema objects (the table's texts parse)
  for (const auto& r : rows) {
    if (r.body_schema.empty()) continue;
    EXPECT_FALSE(json::parse(r.body_schema, nullptr, false).is_discarded()) << r.path;
  }
}

TEST(OpenApi, QueryParametersOfTheDocumentAreAccepted) {
  ApiFixture f;
  mcemu::led::Leds leds;
  leds.power_up({192, 168, 2, 150});
  f.services.led = [&leds](std::string_view query) { return led_response(leds, 0, query); };
  for (const auto& r : Router::route_docs()) {
    if (r.method != Method::get) continue;
    // each parameter alone, and all of them at once (fromMs and toMs of /led go together)
    std::string all;
    for (const auto& q : r.query) {
      const std::string item = std::string(q.name) + "=" + (q.name == "channels" ? "refgo" : "1");
      all += (all.empty() ? "" : "&") + item;
      const auto resp = f.call("GET", sample_path(std::string(r.path)) + "?" + item);
      if (r.path != "/api/v1/led") {
        EXPECT_EQ(resp.status, 200) << r.path << "?" << q.name;
      }
    }
    if (!all.empty()) {
      EXPECT_EQ(f.call("GET", sample_path(std::string(r.path)) + "?" + all).status, 200) << all;
    }
  }
}

// The channels the document names for GET /api/v1/trace are the trace's channels, all of them.
TEST(OpenApi, TheTraceChannelsOfTheDocumentAreTheTracesOwn) {
  ApiFixture f;
  const json doc = f.json_of(f.call("GET", "/api/v1/openapi.json"));
  std::string text;
  for (const auto& p : doc["paths"]["/api/v1/trace"]["get"]["parameters"]) {
    if (p["name"] == "channels") text = p["description"].get<std::string>();
  }
  ASSERT_FALSE(text.empty());
  for (std::size_t i = 0; i < mcemu::trace::k_channel_count; ++i) {
    const auto name = std::string(mcemu::trace::to_string(static_cast<mcemu::trace::Channel>(i)));
    EXPECT_NE(text.find(" " + name + (i + 1 < mcemu::trace::k_channel_count ? "," : " ")), std::string::npos) << name;
    EXPECT_EQ(f.call("GET", "/api/v1/trace?channels=" + name).status, 200) << name;
  }
}

// ---- §8.1 info, §8.10 clock -----------------------------------------------------------------

TEST(Router, InfoWithScriptingAndClock) {
  ApiFixture f;
  auto j = f.get("/api/v1/info");
  EXPECT_EQ(j["emulator"], "mcemu");
  EXPECT_EQ(j["model"], "MC349");
  EXPECT_EQ(j["scripting"], (json{{"available", false}, {"engine", nullptr}}));
  EXPECT_EQ(j["clock"], (json{{"mode", "real"}, {"scale", 1}}));
  f.services.clock = [] { return ClockInfo{"scaled", 2.5}; };
  f.make_router();
  j = f.get("/api/v1/info");
  EXPECT_EQ(j["clock"], (json{{"mode", "scaled"}, {"scale", 2.5}}));
}

TEST(Router, ClockAdvanceOnlyInManualMode) {
  ApiFixture f;
  std::vector<std::uint64_t> advanced;
  std::function<void(std::uint64_t)> pending;
  f.services.advance_clock = [&](std::uint64_t ms, std::function<void(std::uint64_t)> done) {
    advanced.push_back(ms);
    pending = std::move(done);
  };
  f.make_router();
  auto r = f.call("POST", "/api/v1/clock/advance", R"({"ms": 10})");
  EXPECT_EQ(r.status, 409) << "real clock";
  EXPECT_EQ(f.json_of(r)["error"]["code"], "conflict");
  EXPECT_TRUE(advanced.empty());

  f.services.clock = [] { return ClockInfo{"manual", 0}; };
  f.make_router();
  EXPECT_EQ(f.get("/api/v1/clock"), (json{{"mode", "manual"}, {"scale", 0}, {"timeMs", f.core.time_ms()}}));
  for (const char* bad : {R"({"ms": 0})", R"({"ms": 3600001})", R"({"ms": -1})", R"({"ms": "5"})", R"({})",
                          R"({"ms": 5, "x": 1})", R"({"ms": 1.5})"}) {
    EXPECT_EQ(f.call("POST", "/api/v1/clock/advance", bad).status, 400) << bad;
  }
  EXPECT_TRUE(advanced.empty());
  std::optional<Response> out;
  f.r().handle(make_request("POST", "/api/v1/clock/advance", "application/json", R"({"ms": 3600000})"),
               [&](Response resp) { out = resp; });
  EXPECT_EQ(advanced, std::vector<std::uint64_t>{3600000});
  EXPECT_FALSE(out) << "answers after the last step";
  pending(4242);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->status, 200);
  EXPECT_EQ(f.json_of(*out), (json{{"timeMs", 4242}}));

  f.services.advance_clock = nullptr;
  f.make_router();
  EXPECT_EQ(f.call("POST", "/api/v1/clock/advance", R"({"ms": 1})").status, 503);
}

// ---- §8.3 objects ---------------------------------------------------------------------------

TEST(Router, ObjectsReadAndWrite) {
  ApiFixture f;
  auto r = f.call("GET", "/api/v1/objects/0x6083/0");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(f.json_of(r)["value"], 1000);
  EXPECT_EQ(f.json_of(r)["index"], "6083h");
  EXPECT_EQ(f.json_of(r)["sub"], "00h");
  r = f.call("PUT", "/api/v1/objects/6083h/00h", R"({"value": 1500})");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(f.json_of(r), (json{{"ok", true}, {"value", 1500}}));
  EXPECT_EQ(f.n(0x6083, 0), 1500);
  r = f.call("PUT", "/api/v1/objects/6041/0", R"({"value": 1})");
  EXPECT_EQ(r.status, 409);
  EXPECT_EQ(f.json_of(r)["error"], (json{{"code", "abort"},
                                         {"abortCode", "06010002h"},
                                         {"message", std::string(od::description(od::AbortCode::read_only))}}));
  EXPECT_EQ(f.json_of(f.call("GET", "/api/v1/objects/7000/0"))["error"]["abortCode"], "06020000h");
  EXPECT_EQ(f.call("GET", "/api/v1/objects/7000/0").status, 404);
  EXPECT_EQ(f.call("GET", "/api/v1/objects/6041/1").status, 404);
  EXPECT_EQ(f.call("GET", "/api/v1/objects/60zz/0").status, 400);
  r = f.call("POST", "/api/v1/objects/read", R"({"objects": [["6083", 0], ["7000", 0], [24707, "0h"]]})");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(f.json_of(r)["values"], (json{1500, {{"abortCode", "06020000h"}}, 1500}));
  const auto all = f.get("/api/v1/objects");
  EXPECT_EQ(all.size(), f.od.size());
  EXPECT_EQ(all[0].size(), 7u) << all[0].dump();
}

// GET /api/v1/objects is written without a document (web/api/handlers_drive.cpp): its text must be
// what dump_json() prints for the document of web.md §8.3, byte for byte, also for a string that
// needs escaping and holds bytes that are not UTF-8.
TEST(Router, ObjectListIsTheTextOfItsDocument) {
  ApiFixture f;
  f.services.factory = [](std::uint16_t i, std::uint8_t s) -> std::optional<od::Value> {
    if (i == 0x6083 && s == 0) return od::Value{std::int64_t{-777}};
    return std::nullopt;
  };
  const std::string odd("q\"b\\s\x01\t\xff\xfe \xc3\xa9 end");
  ASSERT_EQ(f.od.write(0x3500, 1, od::Value{odd}, od::Origin::internal), od::AbortCode::none);
  const auto value = [](const od::Value& v) {
    return std::holds_alternative<std::int64_t>(v) ? json(std::get<std::int64_t>(v)) : json(std::get<std::string>(v));
  };
  json expected = json::array();
  f.od.for_each([&](const od::EntryInfo& e, const od::Value&) {
    const auto v = f.od.read(e.index, e.sub);
    const auto factory = f.services.factory(e.index, e.sub);
    expected.push_back({{"index", hex_index(e.index)},
                        {"sub", hex_sub(e.sub)},
                        {"name", std::string(e.name)},
                        {"type", od::to_string(e.type)},
                        {"access", od::to_string(e.access)},
                        {"value", v ? value(*v) : json(nullptr)},
                        {"factory", value(factory ? *factory : e.factory)}});
  });
  const auto all = f.call("GET", "/api/v1/objects");
  ASSERT_EQ(all.status, 200);
  EXPECT_EQ(all.content_type, "application/json");
  EXPECT_EQ(all.body, device::dump_json(expected));
  EXPECT_NE(all.body.find(R"("value":"q\"b\\s\u0001\t)"), std::string::npos);
  const auto one = f.call("GET", "/api/v1/objects/6083/0");
  ASSERT_EQ(one.status, 200);
  for (const auto& e : expected) {
    if (e["index"] == "6083" && e["sub"] == "00") {
      EXPECT_EQ(one.body, device::dump_json(e));
    }
  }
}

TEST(Router, FactoryValuesComeFromTheHook) {
  ApiFixture f;
  f.services.factory = [](std::uint16_t i, std::uint8_t s) -> std::optional<od::Value> {
    if (i == 0x6083 && s == 0) return od::Value{std::int64_t{777}};
    return std::nullopt;
  };
  f.make_router();
  EXPECT_EQ(f.get("/api/v1/objects/6083/0")["factory"], 777);
  EXPECT_EQ(f.get("/api/v1/objects/6084/0")["factory"], f.od.info(0x6084, 0)->factory == od::Value{std::int64_t{1000}}
                                                            ? json(1000)
                                                            : value_json(f.od.info(0x6084, 0)->factory));
}

TEST(Router, StoreCompletesWhenTheHookCompletes) {
  ApiFixture f;
  f.release_store_hooks();
  od::Done parked;
  f.od.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    parked = std::move(*r.done);
    return od::AbortCode::pending;
  });
  std::optional<Response> out;
  f.r().handle(make_request("POST", "/api/v1/store", "application/json", "{}"), [&](Response r) { out = r; });
  EXPECT_FALSE(out) << "no answer before the store completes";
  parked(od::AbortCode::hardware_error);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->status, 409);
  EXPECT_EQ(json::parse(out->body)["error"]["abortCode"], "06060000h");
  EXPECT_EQ(f.api_events().back(), "store 06060000h");
}

TEST(Router, FactoryResetWritesLoad) {
  ApiFixture f;
  f.release_store_hooks();
  std::int64_t written = 0;
  f.od.on_write(0x1011, 1, [&](od::WriteRequest& r) {
    written = std::get<std::int64_t>(r.value);
    return od::AbortCode::none;
  });
  EXPECT_EQ(f.call("POST", "/api/v1/factory-reset", "{}").status, 200);
  EXPECT_EQ(written, 0x64616F6C);
  EXPECT_EQ(f.api_events().back(), "factory-reset ok");
  written = 0;
  const auto r = f.call("POST", "/api/v1/factory-reset", R"({"force": true})");
  EXPECT_EQ(r.status, 400) << "the body is {}";
  EXPECT_NE(f.json_of(r)["error"]["message"].get<std::string>().find("force"), std::string::npos);
  EXPECT_EQ(written, 0) << "nothing written";
  EXPECT_EQ(f.call("POST", "/api/v1/power-cycle", "[]").status, 400);
}

// Bad input never crashes and never corrupts: 4xx with a JSON error, and the entries keep their values.
// object-dictionary.md §3.2: the JSON API is strict. A number outside the entry's data type is a
// 400 (code "range", the range check's abort code) and is never stored as its two's complement;
// the dictionary's earlier checks (existence, access, kind) keep their order and their answers.
TEST(Router, JsonWritesOutsideTheTypeAre400NotTwosComplement) {
  ApiFixture f;
  struct Case {
    const char* target;
    const char* body;
    const char* abort;
  };
  for (const auto& c : {Case{"/api/v1/objects/6083/0", R"({"value": -1})", "06090032h"},
                        Case{"/api/v1/objects/6083/0", R"({"value": -2147483648})", "06090032h"},
                        Case{"/api/v1/objects/6083/0", R"({"value": 4294967296})", "06090031h"},
                        Case{"/api/v1/objects/6073/0", R"({"value": 65536})", "06090031h"},
                        Case{"/api/v1/objects/6073/0", R"({"value": -1})", "06090032h"},
                        Case{"/api/v1/objects/6098/0", R"({"value": 128})", "06090031h"},
                        Case{"/api/v1/objects/6098/0", R"({"value": -129})", "06090032h"}}) {
    const auto before = f.get("/api/v1/objects");
    const auto r = f.call("PUT", c.target, c.body);
    EXPECT_EQ(r.status, 400) << c.target << " " << c.body;
    EXPECT_EQ(r.content_type, "application/json");
    const auto e = f.json_of(r)["error"];
    EXPECT_EQ(e["code"], "range") << e.dump();
    EXPECT_EQ(e["abortCode"], c.abort) << c.target << " " << c.body;
    EXPECT_NE(e["message"].get<std::string>().find(" is outside "), std::string::npos) << e.dump();
    EXPECT_EQ(f.get("/api/v1/objects"), before) << "nothing stored: " << c.body;
  }
  // the message names the type and its range
  EXPECT_EQ(f.json_of(f.call("PUT", "/api/v1/objects/6083/0", R"({"value": -1})"))["error"]["message"],
            "-1 is outside UNSIGNED32 (0 … 4294967295)");
  // the edges of the types are stored
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/6098/0", R"({"value": -128})").status, 200);
  EXPECT_EQ(f.n(0x6098, 0), -128);
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/6083/0", R"({"value": 20000})").status, 200);
  // earlier checks answer first: a read-only entry, a missing one, a string for a number
  auto r = f.call("PUT", "/api/v1/objects/6041/0", R"({"value": -1})");
  EXPECT_EQ(r.status, 409);
  EXPECT_EQ(f.json_of(r)["error"]["abortCode"], "06010002h");
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/7000/0", R"({"value": -1})").status, 404);
  EXPECT_EQ(f.json_of(f.call("PUT", "/api/v1/objects/6083/0", R"({"value": "-1"})"))["error"]["abortCode"],
            "06070010h");
  // the journal (web.md §8.6, channel api) records the refusal
  const auto journal = f.api_events();
  EXPECT_NE(std::find(journal.begin(), journal.end(), "PUT 6083h.00h = -1 06090032h"), journal.end());
}

struct BadCall {
  const char* method;
  const char* target;
  const char* body;
  int status;
};

class RouterBadInput : public ::testing::TestWithParam<BadCall> {};

TEST_P(RouterBadInput, Is4xxJsonAndChangesNothing) {
  ApiFixture f;
  const auto& c = GetParam();
  const std::int64_t mode = f.n(0x6060, 0);
  const auto r = f.call(c.method, c.target, c.body, "application/json");
  EXPECT_EQ(r.status, c.status) << r.body;
  const auto body = json::parse(r.body, nullptr, false);
  ASSERT_FALSE(body.is_discarded()) << r.body;
  EXPECT_TRUE(body.contains("error")) << r.body;
  EXPECT_EQ(f.n(0x6083, 0), 1000);
  EXPECT_EQ(f.n(0x6060, 0), mode);
  EXPECT_EQ(f.n(0x6040, 0), 0);
}

INSTANTIATE_TEST_SUITE_P(
    Table, RouterBadInput,
    ::testing::Values(BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": "abc"})", 409},  // 06070010h
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 1.5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": null})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": [1]})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": {"a": 1}})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"val": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"([1500])", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"(1500)", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", "", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", "\xFF\xFE{", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 18446744073709551615})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 18446744073709551616})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 1e300})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": -2147483649})", 400},  // range
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": 4294967296})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/0", R"({"value": -1})", 400},
                      BadCall{"PUT", "/api/v1/objects/6060/0", R"({"value": 99})", 409},
                      BadCall{"PUT", "/api/v1/objects/6083/256", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/10000/0", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects//0", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/6083/", R"({"value": 5})", 400},
                      BadCall{"PUT", "/api/v1/objects/-6083/0", R"({"value": 5})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": "6083"})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [[1]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [["6083"]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [["6083", "zz"]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({"objects": [[null, 0]]})", 400},
                      BadCall{"POST", "/api/v1/objects/read", R"({})", 400},
                      BadCall{"POST", "/api/v1/objects/read", "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]", 400},
                      BadCall{"POST", "/api/v1/refgo", R"({"line": 5})", 400},
                      BadCall{"POST", "/api/v1/refgo", R"({"line": "PWC\r"})", 400},
                      BadCall{"POST", "/api/v1/refgo", R"({"line": "G100\nPWC"})", 400},
                      BadCall{"POST", "/api/v1/refgo", R"({})", 400},
                      BadCall{"POST", "/api/v1/refgo", "{\"line\": \"\xC3\"}", 400},
                      BadCall{"PUT", "/api/v1/settings", R"({"scriptStrict": 1})", 400},
                      BadCall{"PUT", "/api/v1/io/physical-inputs", R"({"set": [5]})", 409},
                      BadCall{"POST", "/api/v1/faults", R"({"kind": "drive.inject", "cause": "x"})", 400}));

TEST(Router, HugeNestingIsRefusedWithoutCrashing) {
  ApiFixture f;
  const std::string deep(1024 * 1024, '[');
  EXPECT_EQ(f.call("POST", "/api/v1/objects/read", deep).status, 400);
  EXPECT_EQ(f.call("POST", "/api/v1/faults", deep).status, 400);
  std::string balanced(200000, '[');
  balanced += std::string(200000, ']');
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", balanced).status, 400);
}

TEST(Router, ObjectWritesAreJournaled) {
  ApiFixture f;
  f.call("PUT", "/api/v1/objects/6083/0", R"({"value": 1500})");
  f.call("PUT", "/api/v1/objects/6041/0", R"({"value": 1})");
  const auto events = f.api_events();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0], "PUT 6083h.00h = 1500 ok");
  EXPECT_EQ(events[1], "PUT 6041h.00h = 1 06010002h");
}

// ---- §8.4 RefGo -------------------------------------------------------------------------------

TEST(Router, RefgoLineThroughTheInterpreter) {
  ApiFixture f;
  f.step(5);
  auto j = f.refgo("OR6041,0,h");
  EXPECT_EQ(j, (json{{"reply", "OR6041,0,H\r\nOR6041,0,40h\r\n>"}, {"answer", "OR6041,0,40h"}, {"ok", true}}));
  j = f.refgo("OW6041,0,5");
  EXPECT_EQ(j["answer"], "OW6041,0,5,ERROR,06010002h");
  EXPECT_EQ(j["ok"], false);
  j = f.refgo("PWC");
  EXPECT_EQ(j, (json{{"reply", "PWC\r\n>"}, {"answer", nullptr}, {"ok", true}}));
  j = f.refgo("");
  EXPECT_EQ(j, (json{{"reply", ">"}, {"answer", nullptr}, {"ok", true}}));
  j = f.refgo("tp\t");  // control bytes filtered as on TCP (TAB → space)
  EXPECT_EQ(j["reply"].get<std::string>().substr(0, 5), "TP \r\n");
  j = f.refgo(std::string(255, ' '));
  EXPECT_EQ(j["reply"], ">") << "255 bytes is not over-long";
  j = f.refgo(std::string(256, 'T'));
  EXPECT_EQ(j, (json{{"reply", ">"}, {"answer", nullptr}, {"ok", true}})) << "over-long (refgo.md §2.4)";
  j = f.refgo("SP123" + std::string(300, '\x01'));  // control bytes do not count (refgo.md §2.4)
  EXPECT_EQ(j["reply"], "SP123\r\n>");
  EXPECT_EQ(f.n(0x6081, 0), 123);
  const auto events = f.api_events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front(), R"(refgo "OR6041,0,h" -> "OR6041,0,H\r\nOR6041,0,40h\r\n>")");
}

TEST(Router, RefgoStoreAnswersLater) {
  ApiFixture f;
  f.release_store_hooks();
  od::Done parked;
  f.od.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    parked = std::move(*r.done);
    return od::AbortCode::pending;
  });
  std::optional<Response> out;
  f.r().handle(make_request("POST", "/api/v1/refgo", "application/json", R"({"line": "OW1010,1,1702257011"})"),
               [&](Response r) { out = r; });
  EXPECT_FALSE(out);
  parked(od::AbortCode::none);
  ASSERT_TRUE(out);
  EXPECT_EQ(f.json_of(*out)["answer"], "OW1010,1,1702257011,OK");
}

// ---- §8.5 I/O -----------------------------------------------------------------------------------

TEST(Router, IoAndPhysicalInputs) {
  ApiFixture f;  // MC349: pins IN1…IN4
  f.step(2);
  EXPECT_EQ(f.get("/api/v1/io"), (json{{"effective", 0}, {"physical", 0}, {"virtual", 0}, {"outputs", 0}}));
  auto r = f.call("PUT", "/api/v1/io/physical-inputs", R"({"mask": 65536})");
  ASSERT_EQ(r.status, 200) << r.body;
  f.od.write(0x3510, 1, od::Value{std::int64_t{262144}}, od::Origin::web);
  f.step(1);
  EXPECT_EQ(f.get("/api/v1/io"),
            (json{{"effective", 327680}, {"physical", 65536}, {"virtual", 262144}, {"outputs", 0}}))
      << "the example of web.md §8.5";
  r = f.call("PUT", "/api/v1/io/physical-inputs", R"({"set": [2, 3], "clear": [1]})");
  EXPECT_EQ(f.json_of(r)["physical"], (1 << 17) | (1 << 18));
  // IN5 has no pin on MC349: 409 naming it, and nothing changes
  r = f.call("PUT", "/api/v1/io/physical-inputs", R"({"set": [4, 5]})");
  EXPECT_EQ(r.status, 409);
  EXPECT_NE(f.json_of(r)["error"]["message"].get<std::string>().find("IN5"), std::string::npos);
  EXPECT_EQ(f.get("/api/v1/io")["physical"], (1 << 17) | (1 << 18)) << "IN4 was not set either";
  r = f.call("PUT", "/api/v1/io/physical-inputs", R"({"mask": 2097152})");  // bit 21 = IN6
  EXPECT_EQ(r.status, 409);
  EXPECT_EQ(f.call("PUT", "/api/v1/io/physical-inputs", R"({"mask": 0})").status, 200)
      << "0 for pin-less inputs is fine";
  EXPECT_EQ(f.get("/api/v1/io")["physical"], 0);
  for (const char* bad :
       {R"({"mask": 1})", R"({"mask": -1})", R"({"mask": 65536, "set": [1]})", R"({"set": [0]})", R"({"set": [11]})",
        R"({"set": 1})", R"({"set": [1], "clear": [1]})", R"({})", R"({"levels": 1})", R"({"set": ["1"]})"}) {
    EXPECT_EQ(f.call("PUT", "/api/v1/io/physical-inputs", bad).status, 400) << bad;
  }
  EXPECT_EQ(f.get("/api/v1/io")["physical"], 0);
}

// ---- §8.7 LED, UDP, script ----------------------------------------------------------------------

TEST(Router, LedAndUdpDelegateToTheirHooks) {
  ApiFixture f;
  EXPECT_EQ(f.call("GET", "/api/v1/led").status, 503);
  EXPECT_EQ(f.call("GET", "/api/v1/udp").status, 503);
  std::string led_query = "-";
  f.services.led = [&led_query](std::string_view query) {
    led_query = std::string(query);
    Response r;
    r.body = json{{"timeMs", 5}, {"green", {{"on", true}}}}.dump();
    return r;
  };
  f.services.udp = [] {
    UdpView v;
    v.listeners.push_back({"127.0.0.1", 5000, 1234, "2026-01-15T10:15:02.123Z"});
    v.backlog_bytes = 10;
    v.backlog_messages = 1;
    v.datagrams_sent = 3;
    v.datagrams_dropped = 1;
    v.datagrams_received = 2;
    v.ignored_payloads = 1;
    v.messages = {"Hello\r\n"};
    return v;
  };
  f.make_router();
  EXPECT_EQ(f.get("/api/v1/led"), (json{{"timeMs", 5}, {"green", {{"on", true}}}}));
  EXPECT_EQ(led_query, "");
  EXPECT_EQ(f.call("GET", "/api/v1/led?fromMs=0&toMs=10").status, 200);
  EXPECT_EQ(led_query, "fromMs=0&toMs=10");
  EXPECT_EQ(f.get("/api/v1/udp"),
            (json{{"listeners",
                   {{{"address", "127.0.0.1"},
                     {"port", 5000},
                     {"registeredMs", 1234},
                     {"registeredWall", "2026-01-15T10:15:02.123Z"}}}},
                  {"backlog", {{"bytes", 10}, {"messages", 1}}},
                  {"counters",
                   {{"datagramsSent", 3}, {"datagramsDropped", 1}, {"datagramsReceived", 2}, {"ignoredPayloads", 1}}},
                  {"messages", {"Hello\r\n"}}}));
}

TEST(Router, ScriptEndpointsAre503WithoutAnEngine) {
  ApiFixture f;
  for (const auto& [method, path] :
       std::vector<std::pair<std::string, std::string>>{{"GET", "/api/v1/script"},
                                                        {"PUT", "/api/v1/script"},
                                                        {"POST", "/api/v1/script/start"},
                                                        {"POST", "/api/v1/script/stop"},
                                                        {"POST", "/api/v1/script/pause"},
                                                        {"POST", "/api/v1/script/resume"},
                                                        {"PUT", "/api/v1/script/autostart"}}) {
    const auto r = f.call(method, path, "{}", "application/json");
    EXPECT_EQ(r.status, 503) << path;
    EXPECT_EQ(f.json_of(r)["error"],
              (json{{"code", "unavailable"}, {"message", "script engine not available in this version"}}));
  }
  EXPECT_EQ(f.n(0x3500, 4), 0) << "autostart unchanged";
}

class FakeScript final : public ScriptControl {
 public:
  bool available() const override { return usable; }
  std::string engine() const override { return usable ? "fake 1.0" : "no python3 here"; }
  ScriptView view() const override {
    ScriptView v;
    v.id = id;
    v.state = state;
    v.crc32 = 0x1A2B3C4D;
    v.source = source;
    return v;
  }
  std::optional<std::string> upload(std::string s) override {
    if (s == "bad") return "syntax error";
    source = std::move(s);
    return std::nullopt;
  }
  void start() override { calls.push_back("start"), state = "RUN"; }
  void stop() override { calls.push_back("stop"), state = "OFF"; }
  void pause() override { calls.push_back("pause"), state = "BRK"; }
  void resume() override { calls.push_back("resume"), state = "RUN"; }
  void kill() override { calls.push_back("kill"); }
  void code_act(int n) override { calls.push_back("codeAct " + std::to_string(n)); }
  PythonStatus status() const override { return PythonStatus{state, 7}; }
  int refgo_attach_mode() const override { return 2; }
  SandboxView sandbox() const override { return sandbox_view; }

  std::string id = "demo", state = "OFF", source;
  bool usable = true;
  SandboxView sandbox_view;
  std::vector<std::string> calls;
};

TEST(Router, ScriptEndpointsForwardToTheEngine) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  EXPECT_EQ(f.get("/api/v1/info")["scripting"], (json{{"available", true}, {"engine", "fake 1.0"}}));
  auto j = f.get("/api/v1/script");
  EXPECT_EQ(j["crc32"], "1A2B3C4Dh");
  EXPECT_EQ(f.call("PUT", "/api/v1/script", "print(1)\n", "text/x-python").status, 200);
  EXPECT_EQ(script.source, "print(1)\n");
  EXPECT_EQ(f.call("PUT", "/api/v1/script", "", "text/x-python").status, 400);
  EXPECT_EQ(f.call("PUT", "/api/v1/script", "bad", "text/x-python").status, 400);
  EXPECT_EQ(f.call("PUT", "/api/v1/script", std::string(65537, 'x'), "text/x-python").status, 413);
  EXPECT_EQ(f.call("PUT", "/api/v1/script", std::string(65536, 'x'), "text/x-python").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/script/start", "").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/script/pause", "{}").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/script/resume", "{}").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/script/stop", "{}").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/script/stop", "{}", "text/plain").status, 415);
  EXPECT_EQ(script.calls, (std::vector<std::string>{"start", "pause", "resume", "stop"}));
  EXPECT_EQ(f.call("PUT", "/api/v1/script/autostart", R"({"on": true})").status, 200);
  EXPECT_EQ(f.n(0x3500, 4), 1);
  EXPECT_EQ(f.call("PUT", "/api/v1/script/autostart", R"({"on": 1})").status, 400);
  const auto s = f.status();
  EXPECT_EQ(s["python"]["line"], 7);
  EXPECT_EQ(s["refgo"]["attachMode"], 2);
  EXPECT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "script.kill"})").status, 409) << "nothing runs";
  EXPECT_EQ(script.calls.back(), "stop");
  script.state = "RUN";
  EXPECT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "script.kill"})").status, 201);
  EXPECT_EQ(script.calls.back(), "kill");
}

// docs/security.md: /api/v1/info says whether scripts run in the sandbox, what it is, or why not.
TEST(Router, InfoReportsTheScriptSandbox) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  EXPECT_FALSE(f.get("/api/v1/info")["scripting"].contains("sandbox")) << "nothing known, nothing said";
  script.sandbox_view = {true, true, false, "bubblewrap 0.8.0: no network"};
  EXPECT_EQ(f.get("/api/v1/info")["scripting"]["sandbox"],
            (json{{"active", true}, {"unsafe", false}, {"description", "bubblewrap 0.8.0: no network"}}));
  script.sandbox_view = {true, false, true, "UNSAFE: scripts run without the script sandbox"};
  EXPECT_EQ(f.get("/api/v1/info")["scripting"]["sandbox"],
            (json{{"active", false}, {"unsafe", true}, {"reason", "UNSAFE: scripts run without the script sandbox"}}));
  script.usable = false;
  script.sandbox_view = {true, false, false, "scripts do not run because the script sandbox cannot be set up (x)"};
  const auto info = f.get("/api/v1/info")["scripting"];
  EXPECT_EQ(info["available"], false);
  EXPECT_EQ(info["sandbox"]["reason"], "scripts do not run because the script sandbox cannot be set up (x)");
}

// scripting.md §10.1.8: no usable python3 — the start is made (its UDP lines say so) and answered
// 503; everything else works.
TEST(Router, ScriptEngineUnavailable) {
  ApiFixture f;
  FakeScript script;
  script.usable = false;
  f.services.script = &script;
  f.make_router();
  EXPECT_EQ(f.get("/api/v1/info")["scripting"],
            (json{{"available", false}, {"engine", nullptr}, {"reason", "no python3 here"}}));
  EXPECT_EQ(f.call("PUT", "/api/v1/script", "print(1)\n", "text/x-python").status, 200);
  const auto r = f.call("POST", "/api/v1/script/start", "{}");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(f.json_of(r)["error"]["message"], "script engine unavailable: no python3 here");
  EXPECT_EQ(script.calls, (std::vector<std::string>{"start"}));
  EXPECT_EQ(f.call("GET", "/program.html?codeAct=3").status, 200) << "web.md §6.2: 200 also when unavailable";
  EXPECT_EQ(f.call("POST", "/api/v1/script/stop", "{}").status, 200);
}

// ---- web.md §6: /program.html --------------------------------------------------------------------

// The request python-requests 2.28 builds for Fullmo's uploader (files={field: (name, bytes,
// "text/x-python")}).
Request upl_upload(const std::string& script, const std::string& field = "Python script file for MovingCap CODE") {
  const std::string boundary = "8f1a2b3c4d5e6f708192a3b4c5d6e7f8";
  Request r = make_request("POST", "/program.html", "multipart/form-data; boundary=" + boundary,
                           "--" + boundary + "\r\nContent-Disposition: form-data; name=\"" + field +
                               "\"; filename=\"demo.py\"\r\nContent-Type: text/x-python\r\n\r\n" + script + "\r\n--" +
                               boundary + "--\r\n");
  r.headers = {{"host", "127.0.0.1:8080"},           {"user-agent", "python-requests/2.28.1"},
               {"accept-encoding", "gzip, deflate"}, {"accept", "*/*"},
               {"connection", "keep-alive"},         {"content-length", std::to_string(r.body.size())}};
  return r;
}

Response handled(ApiFixture& f, const Request& r) {
  Response out;
  int calls = 0;
  f.r().handle(r, [&](Response resp) {
    out = std::move(resp);
    ++calls;
  });
  EXPECT_EQ(calls, 1);
  return out;
}

TEST(ProgramHtml, UploadAsFullmosUploaderSendsIt) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  const std::string text = "#id demo\r\nprint('x')\r\n\r\n";  // kept byte for byte, CRLFs and the empty line too
  const auto r = handled(f, upl_upload(text));
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
  EXPECT_EQ(header(r, "Cache-Control"), "no-store");
  EXPECT_EQ(script.source, text);
  EXPECT_NE(r.body.find("name=\"Python script file for MovingCap CODE\""), std::string::npos) << "the Code page";
  EXPECT_EQ(f.api_events().back(), "script upload (program.html), " + std::to_string(text.size()) + " bytes");
}

TEST(ProgramHtml, RefusedUploadsChangeNothing) {
  ApiFixture f;
  FakeScript script;
  script.source = "old";
  f.services.script = &script;
  f.make_router();
  struct Case {
    Request req;
    int status;
  };
  Request not_multipart = make_request("POST", "/program.html", "text/x-python", "print(1)\n");
  Request bad_body = upl_upload("print(1)");
  bad_body.body = bad_body.body.substr(0, bad_body.body.size() - 40);  // no closing delimiter
  for (auto& c : std::vector<Case>{{upl_upload("print(1)", "python script file for movingcap code"), 400},
                                   {upl_upload("print(1)", "file"), 400},
                                   {upl_upload(""), 400},
                                   {upl_upload(std::string(65537, '#')), 413},
                                   {not_multipart, 400},
                                   {bad_body, 400}}) {
    const auto r = handled(f, c.req);
    EXPECT_EQ(r.status, c.status) << c.req.body.substr(0, 120);
    EXPECT_NE(r.body.find("id=\"code-error\""), std::string::npos) << "the Code page with an error text";
  }
  EXPECT_EQ(script.source, "old");
  EXPECT_EQ(handled(f, upl_upload(std::string(65536, '#'))).status, 200) << "65 536 bytes is the limit";
}

// web.md §6.1: a refused upload answers the Code page with the refusal inside the page — in its
// upload section, after the menu bar and the page's heading — not above the menu bar.
TEST(ProgramHtml, TheRefusalIsShownInTheUploadSection) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  const auto r = handled(f, upl_upload(""));
  ASSERT_EQ(r.status, 400);
  const auto& b = r.body;
  const auto note =
      b.find("<p id=\"code-error\" class=\"notice error\" role=\"alert\">upload refused: the script file is empty</p>");
  ASSERT_NE(note, std::string::npos) << b;
  EXPECT_LT(b.find("id=\"menubar\""), note) << "after the menu bar";
  EXPECT_LT(b.find("<main"), note);
  EXPECT_LT(b.find("id=\"code-file-hint\""), note) << "under the upload controls";
  EXPECT_LT(note, b.find("</form>"));
  EXPECT_EQ(b.find("<!--code-error-->"), std::string::npos) << "the marker is replaced";
  EXPECT_EQ(b.find("id=\"code-error\"", note + 10), std::string::npos) << "once";
  EXPECT_NE(handled(f, upl_upload("print(1)\n")).body.find("<!--code-error-->"), std::string::npos)
      << "an accepted upload shows no note";
}

TEST(ProgramHtml, CodeActPerformsTheActionAndAnswersThePage) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  for (const char* q : {"3", "4", "1", "2", "5", "6", "7", "0", "-1"}) {
    const auto r = f.call("GET", std::string("/program.html?codeAct=") + q);
    EXPECT_EQ(r.status, 200) << q;
    EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
  }
  EXPECT_EQ(script.calls, (std::vector<std::string>{"codeAct 3", "codeAct 4", "codeAct 1", "codeAct 2", "codeAct 5",
                                                    "codeAct 6", "codeAct 7", "codeAct 0", "codeAct -1"}))
      << "the engine ignores the numbers it has no action for";
  script.calls.clear();
  for (const char* t : {"/program.html?codeAct=x", "/program.html?codeAct=", "/program.html?codeAct=3x",
                        "/program.html", "/program.html?other=1", "/program.html?codeAct=3&codeAct=4"}) {
    EXPECT_EQ(f.call("GET", t).status, 200) << t;
  }
  EXPECT_TRUE(script.calls.empty()) << "non-numeric, missing or repeated codeAct: ignored";
  EXPECT_EQ(f.call("HEAD", "/program.html?codeAct=3").status, 200);
  EXPECT_TRUE(script.calls.empty()) << "HEAD never performs an action (web.md §1.4)";
  const auto put = f.call("PUT", "/program.html", "x", "text/plain");
  EXPECT_EQ(put.status, 405);
  EXPECT_EQ(header(put, "Allow"), "GET, HEAD, POST");
}

TEST(ProgramHtml, CrossSiteRequestsAre403AndChangeNothing) {
  ApiFixture f;
  FakeScript script;
  f.services.script = &script;
  f.make_router();
  Request upload = upl_upload("print(1)");
  upload.headers.emplace_back("origin", "http://evil.example");
  EXPECT_EQ(handled(f, upload).status, 403);
  Request start = make_request("GET", "/program.html?codeAct=3");
  start.headers = {{"host", "127.0.0.1:8080"}, {"sec-fetch-site", "cross-site"}};
  EXPECT_EQ(handled(f, start).status, 403);
  EXPECT_TRUE(script.calls.empty());
  EXPECT_TRUE(script.source.empty());
  Request same = make_request("GET", "/program.html?codeAct=3");
  same.headers = {{"host", "127.0.0.1:8080"}, {"origin", "http://127.0.0.1:8080"}, {"sec-fetch-site", "same-origin"}};
  EXPECT_EQ(handled(f, same).status, 200) << "the page's own buttons";
  EXPECT_EQ(script.calls, (std::vector<std::string>{"codeAct 3"}));
}

TEST(ProgramHtml, ThePlainCodePageShowsTheScript) {
  ApiFixture f;
  FakeScript script;
  script.state = "RUN";
  script.source = "#id demo\nif a < b: print('<&>')\n";
  f.services.script = &script;
  f.make_router();
  const auto r = f.call("GET", "/program.html");
  ASSERT_EQ(r.status, 200);
  if (!assets::find("/program.html")) {  // the plain page of a build without the web UI's Code page
    EXPECT_NE(r.body.find("<span id=\"code-status\">RUN demo</span>"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("if a &lt; b: print('&lt;&amp;&gt;')"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("href=\"/program.html?codeAct=4\">Stop</a>"), std::string::npos);
  } else {  // the web UI's Code page, rendered with the script's state (web/api/pages.hpp)
    EXPECT_EQ(r.body.find("{{"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("<span id=\"code-status\" class=\"mono\">RUN demo</span>"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("if a &lt; b: print(&#39;&lt;&amp;&gt;&#39;)"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("id=\"code-stop\" data-act=\"4\""), std::string::npos);
  }
}

TEST(ProgramHtml, WithoutAnEngineTheActionsAre503) {
  ApiFixture f;
  EXPECT_EQ(handled(f, upl_upload("print(1)")).status, 503);
  EXPECT_EQ(f.call("GET", "/program.html?codeAct=3").status, 503);
  EXPECT_EQ(f.call("GET", "/program.html").status, 200);
}

// ---- §8.8 power cycle, EDS, §10 ws ----------------------------------------------------------------

TEST(Router, PowerCycleCallsTheHookAndAnswersWhenDone) {
  ApiFixture f;
  EXPECT_EQ(f.call("POST", "/api/v1/power-cycle", "{}").status, 503);
  std::function<void()> done;
  f.services.power_cycle = [&](std::function<void()> d) { done = std::move(d); };
  f.make_router();
  std::optional<Response> out;
  f.r().handle(make_request("POST", "/api/v1/power-cycle", "application/json", ""), [&](Response r) { out = r; });
  ASSERT_TRUE(done);
  EXPECT_FALSE(out);
  done();
  ASSERT_TRUE(out);
  EXPECT_EQ(out->status, 200);
  EXPECT_EQ(f.json_of(*out)["ok"], true);
  EXPECT_EQ(f.api_events().back(), "power-cycle");
}

TEST(Router, EdsFromTheHook) {
  ApiFixture f;
  EXPECT_EQ(f.call("GET", "/api/v1/eds").status, 503);
  f.services.eds = [] { return std::string("[FileInfo]\r\nFileName=MC349.eds\r\n"); };
  f.make_router();
  const auto r = f.call("GET", "/api/v1/eds");
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "text/plain; charset=utf-8");
  EXPECT_EQ(r.body, "[FileInfo]\r\nFileName=MC349.eds\r\n");
}

TEST(Router, WebSocketPathWithoutUpgradeIs426) {
  ApiFixture f;
  const auto r = f.call("GET", "/api/v1/ws");
  EXPECT_EQ(r.status, 426);
  EXPECT_EQ(header(r, "Upgrade"), "websocket");
}

// ---- docs/security.md: --api-token ----------------------------------------------------------------

Request with_auth(Request r, std::string value) {
  r.headers.emplace_back("authorization", std::move(value));
  return r;
}

TEST(ApiToken, EmulatorEndpointsNeedItAndTheDrivesOwnStayOpen) {
  ApiFixture f;
  f.services.api_token = "0123456789abcdef-token";
  f.make_router();
  const auto answer = [&](Request req) {
    Response out;
    f.r().handle(req, [&](Response r) { out = std::move(r); });
    return out;
  };
  // the token rows of the table: refused without the token, before anything is looked at
  for (const auto& [method, path, body] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"PUT", "/api/v1/settings", R"({"traceScriptCalls": true})"},
           {"POST", "/api/v1/clock/advance", R"({"ms": 1})"},
           {"POST", "/api/v1/power-cycle", "{}"},
           {"POST", "/api/v1/faults", R"({"kind": "udp.drop"})"},
           {"DELETE", "/api/v1/faults", ""},
           {"DELETE", "/api/v1/faults/f1", ""},
           {"DELETE", "/api/v1/lint", ""}}) {
    for (const char* auth : {"", "Bearer wrong", "Bearer 0123456789abcdef-toke", "Basic 0123456789abcdef-token",
                             "Bearer 0123456789abcdef-token2"}) {
      auto req = make_request(method, path, "application/json", body);
      const auto r = answer(*auth ? with_auth(req, auth) : req);
      EXPECT_EQ(r.status, 401) << method << " " << path << " with '" << auth << "'";
      EXPECT_EQ(f.json_of(r)["error"]["code"], "unauthorized");
      EXPECT_EQ(header(r, "WWW-Authenticate"), "Bearer realm=\"mcemu\"");
    }
    const auto ok =
        answer(with_auth(make_request(method, path, "application/json", body), "bearer  0123456789abcdef-token"));
    EXPECT_NE(ok.status, 401) << method << " " << path;
  }
  EXPECT_EQ(f.get("/api/v1/settings")["traceScriptCalls"], true) << "the authorised PUT was applied";
  // everything the real drive has, and reading the emulator's state, stays open
  EXPECT_EQ(f.call("GET", "/api/v1/info").status, 200);
  EXPECT_EQ(f.call("GET", "/api/v1/settings").status, 200);
  EXPECT_EQ(f.call("GET", "/api/v1/faults").status, 200);
  EXPECT_EQ(f.call("PUT", "/api/v1/objects/6083/0", R"({"value": 2000})", "application/json").status, 200);
  EXPECT_EQ(f.call("POST", "/api/v1/refgo", R"({"line": "TP"})").status, 200);
  EXPECT_NE(f.call("GET", "/index.html").status, 401);
}

TEST(ApiToken, WithoutTheFlagNothingChanges) {
  ApiFixture f;
  f.make_router();
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"traceScriptCalls": true})", "application/json").status, 200);
  EXPECT_EQ(f.call("DELETE", "/api/v1/faults").status, 200);
}

TEST(ApiToken, TheOpenApiDocumentMarksTheTokenRows) {
  ApiFixture f;
  const json doc = f.get("/api/v1/openapi.json");
  EXPECT_EQ(doc["components"]["securitySchemes"]["bearer"]["scheme"], "bearer");
  EXPECT_TRUE(doc["paths"]["/api/v1/settings"]["put"].contains("security"));
  EXPECT_TRUE(doc["paths"]["/api/v1/settings"]["put"]["responses"].contains("401"));
  EXPECT_FALSE(doc["paths"]["/api/v1/settings"]["get"].contains("security"));
  EXPECT_FALSE(doc["paths"]["/api/v1/objects/{index}/{sub}"]["put"].contains("security"));
  std::size_t rows = 0;
  for (const auto& r : Router::route_docs()) rows += r.token ? 1 : 0;
  EXPECT_EQ(rows, 7U) << "settings, clock advance, power cycle, faults (create, clear, remove), lint reset";
}

TEST(ApiToken, BearerMatching) {
  EXPECT_TRUE(bearer_matches("Bearer abc", "abc"));
  EXPECT_TRUE(bearer_matches("BEARER   abc  ", "abc"));
  EXPECT_FALSE(bearer_matches(std::nullopt, "abc"));
  EXPECT_FALSE(bearer_matches("Bearer abc", ""));
  EXPECT_FALSE(bearer_matches("Bearer ab", "abc"));
  EXPECT_FALSE(bearer_matches("Bearer abcd", "abc"));
  EXPECT_FALSE(bearer_matches("Bearer", "abc"));
  EXPECT_FALSE(bearer_matches("Bearerabc", "abc"));
  EXPECT_FALSE(bearer_matches("Token abc", "abc"));
}

// ---- §8.9 settings --------------------------------------------------------------------------------

TEST(Router, RuntimeSettings) {
  ApiFixture f("MC349", json{{"settings", {{"scriptMemoryMiB", 128}}}});  // the start value from --config
  std::vector<RuntimeSettings> changes;
  f.observe_settings([&](const RuntimeSettings& s) { changes.push_back(s); });
  f.make_router();
  EXPECT_EQ(
      f.get("/api/v1/settings"),
      (json{
          {"udpEmulatorNotes", false}, {"scriptStrict", true}, {"scriptMemoryMiB", 128}, {"traceScriptCalls", false}}));
  auto r = f.call("PUT", "/api/v1/settings", R"({"traceScriptCalls": true, "scriptMemoryMiB": 8})");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(f.json_of(r)["scriptMemoryMiB"], 32) << "below 32 is taken as 32";
  EXPECT_EQ(f.json_of(r)["traceScriptCalls"], true);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_TRUE(changes[0].trace_script_calls);
  for (const char* bad : {R"({"nope": true})", R"({"udpEmulatorNotes": "yes"})", R"({"scriptMemoryMiB": 1.5})",
                          R"({"scriptMemoryMiB": -1})", R"({"scriptMemoryMiB": true})", R"([])",
                          R"({"scriptStrict": true, "unknown": 1})", ""}) {
    r = f.call("PUT", "/api/v1/settings", bad);
    EXPECT_EQ(r.status, 400) << bad;
  }
  EXPECT_NE(
      f.json_of(f.call("PUT", "/api/v1/settings", R"({"nope": true})"))["error"]["message"].get<std::string>().find(
          "nope"),
      std::string::npos);
  EXPECT_EQ(f.get("/api/v1/settings")["traceScriptCalls"], true) << "a refused change changes nothing";
  EXPECT_EQ(changes.size(), 1u);
  EXPECT_EQ(f.r().settings().script_memory_mib, 32);
}

// docs/security.md: over HTTP the script settings may be tightened, never relaxed beyond their start
// values — 403, nothing changes, nothing is told to the server.
TEST(Router, RelaxingScriptSettingsOverHttpIs403) {
  ApiFixture f;
  std::vector<RuntimeSettings> changes;
  f.observe_settings([&](const RuntimeSettings& s) { changes.push_back(s); });
  f.make_router();
  for (const char* relax : {R"({"scriptStrict": false})", R"({"scriptMemoryMiB": 257})",
                            R"({"traceScriptCalls": true, "scriptStrict": false})"}) {
    const auto r = f.call("PUT", "/api/v1/settings", relax);
    EXPECT_EQ(r.status, 403) << relax;
    EXPECT_EQ(f.json_of(r)["error"]["code"], "forbidden");
    EXPECT_NE(f.json_of(r)["error"]["message"].get<std::string>().find("config file"), std::string::npos);
  }
  EXPECT_TRUE(changes.empty());
  EXPECT_EQ(f.get("/api/v1/settings")["traceScriptCalls"], false) << "all or nothing";
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptStrict": true, "scriptMemoryMiB": 256})").status, 200);
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptMemoryMiB": 64})").status, 200) << "tightening is fine";
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptMemoryMiB": 256})").status, 200) << "back to the default";
}

TEST(Router, WhatTheConfigFileRelaxedHttpMayRestore) {
  ApiFixture f("MC349", json{{"settings", {{"scriptStrict", false}, {"scriptMemoryMiB", 1024}}}});
  f.make_router();
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptStrict": true, "scriptMemoryMiB": 64})").status, 200);
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptStrict": false, "scriptMemoryMiB": 1024})").status, 200);
  EXPECT_EQ(f.call("PUT", "/api/v1/settings", R"({"scriptMemoryMiB": 1025})").status, 403);
}

TEST(RuntimeSettingsJson, Relaxation) {
  const RuntimeSettings start;
  RuntimeSettings next;
  EXPECT_FALSE(relaxation(start, next));
  next.script_strict = false;
  EXPECT_TRUE(relaxation(start, next));
  next = start;
  next.script_memory_mib = RuntimeSettings::k_default_script_memory_mib + 1;
  EXPECT_TRUE(relaxation(start, next));
  RuntimeSettings small = start;
  small.script_memory_mib = 64;  // a config that starts lower still lets HTTP go up to the default
  next.script_memory_mib = RuntimeSettings::k_default_script_memory_mib;
  EXPECT_FALSE(relaxation(small, next));
  next.udp_emulator_notes = true;
  next.trace_script_calls = true;
  EXPECT_FALSE(relaxation(small, next)) << "the other settings are not the sandbox's business";
}

TEST(RuntimeSettingsJson, AllOrNothing) {
  RuntimeSettings s;
  EXPECT_TRUE(apply_settings(s, json{{"traceScriptCalls", true}, {"bogus", 1}}).has_value());
  EXPECT_FALSE(s.trace_script_calls);
  EXPECT_FALSE(apply_settings(s, json{{"traceScriptCalls", true}, {"scriptMemoryMiB", 512}}).has_value());
  EXPECT_TRUE(s.trace_script_calls);
  EXPECT_EQ(s.script_memory_mib, 512);
  EXPECT_EQ(settings_json(s)["scriptMemoryMiB"], 512);
}

// ---- helpers ----------------------------------------------------------------------------------------

TEST(HexToken, Forms) {
  EXPECT_EQ(parse_hex_token("6041", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("6041h", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("0x6041", 0xFFFF), 0x6041u);
  EXPECT_EQ(parse_hex_token("01h", 0xFF), 1u);
  EXPECT_FALSE(parse_hex_token("100", 0xFF));
  EXPECT_FALSE(parse_hex_token("", 0xFF));
  EXPECT_FALSE(parse_hex_token("h", 0xFF));
}

TEST(Query, PercentDecodingAndErrors) {
  const auto q = parse_query("/x?a=1&b=refgo%2Cudp&c=&d=x+y&&");
  ASSERT_TRUE(q);
  EXPECT_EQ(*q, (std::map<std::string, std::string>{{"a", "1"}, {"b", "refgo,udp"}, {"c", ""}, {"d", "x y"}}));
  EXPECT_FALSE(parse_query("/x?a=%"));
  EXPECT_FALSE(parse_query("/x?a=%4"));
  EXPECT_FALSE(parse_query("/x?a=%G1"));
  EXPECT_FALSE(parse_query("/x?a=1&a=2")) << "a repeated key is ambiguous";
  EXPECT_TRUE(parse_query("/x")->empty());
}

TEST(MediaType, Json) {
  EXPECT_TRUE(is_json_media_type("application/json"));
  EXPECT_TRUE(is_json_media_type("APPLICATION/JSON;charset=utf-8"));
  EXPECT_FALSE(is_json_media_type(""));
  EXPECT_FALSE(is_json_media_type("application/json5"));
}

}  // namespace
}  // namespace mcemu::web::api
