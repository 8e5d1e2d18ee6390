// The web side of a FAULHABER drive (web/README.md "FAULHABER drive"): the status snapshot with
// the MC's footer and status LED (status.cpp), and the page gating of Router::page — the Emulator
// page from its own template at /emulator.html, `/` and the MovingCap pages redirected there, the
// template not served on a MovingCap. A real FH_MC5005 bundle stepped in simulated time.
#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/device_fixture.hpp"
#include "web/api/led_view.hpp"
#include "web/api/pages.hpp"
#include "web/api/router.hpp"
#include "web/api/status.hpp"
#include "web/assets/assets.hpp"

namespace mcemu::web::api {
namespace {

using nlohmann::json;

// ---- footer and LED: table-driven

struct FhFooterCase {
  const char* name;
  FhFooterValues v;
  FhFooter want;
};

FhFooterValues fv(core::PdsState s, std::uint16_t err, std::uint16_t sw, std::int8_t mode, int basic, std::int64_t pos,
                  std::int64_t vel, std::uint16_t in, std::uint16_t out) {
  FhFooterValues v;
  v.state = s;
  v.error_code = err;
  v.statusword = sw;
  v.op_mode_display = mode;
  v.basic_running = basic;
  v.pos = pos;
  v.vel = vel;
  v.inputs = in;
  v.outputs = out;
  return v;
}

class FhFooterTable : public ::testing::TestWithParam<FhFooterCase> {};

TEST_P(FhFooterTable, ExactText) {
  const auto& c = GetParam();
  const FhFooter f = fh_footer(c.v);
  EXPECT_EQ(f.state, c.want.state) << c.name;
  EXPECT_EQ(f.statwd, c.want.statwd) << c.name;
  EXPECT_EQ(f.opmode, c.want.opmode) << c.name;
  EXPECT_EQ(f.basic, c.want.basic) << c.name;
  EXPECT_EQ(f.pos, c.want.pos) << c.name;
  EXPECT_EQ(f.vel, c.want.vel) << c.name;
  EXPECT_EQ(f.io, c.want.io) << c.name;
}

using S = core::PdsState;
INSTANTIATE_TEST_SUITE_P(Rows, FhFooterTable,
                         ::testing::Values(FhFooterCase{"power on",
                                                        fv(S::switch_on_disabled, 0, 0x0040, 0, 0, 0, 0, 0, 0),
                                                        {"Switch on disabled", "StatWd 0040h", "OpMode 0", "BASIC OFF",
                                                         "Pos 0 inc", "Vel 0 rpm", "I........O.."}},
                                           FhFooterCase{
                                               "enabled, moving, program 3",
                                               fv(S::operation_enabled, 0, 0x0027, 1, 3, -45000, 1200, 0x85, 0x2),
                                               {"Operation enabled", "StatWd 0027h", "OpMode 1", "BASIC RUN 3",
                                                "Pos -45000 inc", "Vel 1200 rpm", "I1.3....8O.2"}},
                                           FhFooterCase{"fault with its code",
                                                        fv(S::fault, 0x8611, 0x0008, -1, 0, 7, -3, 0xFF, 0x3),
                                                        {"Fault 8611h", "StatWd 0008h", "OpMode -1", "BASIC OFF",
                                                         "Pos 7 inc", "Vel -3 rpm", "I12345678O12"}},
                                           FhFooterCase{"fault reaction with its code",
                                                        fv(S::fault_reaction_active, 0x3210, 0x000F, 1, 0, 0, 0, 0, 0),
                                                        {"Fault reaction active 3210h", "StatWd 000Fh", "OpMode 1",
                                                         "BASIC OFF", "Pos 0 inc", "Vel 0 rpm", "I........O.."}}));

TEST(FhLed, GreenSteadyEnabledBlinkingReadyRedInFault) {
  const struct {
    S state;
    std::string_view color;
    bool blink;
  } rows[] = {{S::not_ready_to_switch_on, "off", false}, {S::switch_on_disabled, "green", true},
              {S::ready_to_switch_on, "green", true},    {S::switched_on, "green", true},
              {S::operation_enabled, "green", false},    {S::quick_stop_active, "green", true},
              {S::fault_reaction_active, "red", false},  {S::fault, "red", false}};
  for (const auto& r : rows) {
    EXPECT_EQ(fh_led(r.state).color, r.color) << state_name(r.state);
    EXPECT_EQ(fh_led(r.state).blink, r.blink) << state_name(r.state);
  }
}

// ---- a real FH_MC5005 behind the router

struct FhFixture {
  explicit FhFixture(const char* model = "FH_MC5005") : bundle(model) {
    services.info = [this] {
      Info i;
      i.version = "0.1.0";
      i.model = bundle.preset().name;
      i.device_name = bundle.preset().identity.device_name;
      i.display_name = bundle.preset().identity.display_name;
      fill_as_the_server(i);
      return i;
    };
    // as server/drive_web.cpp gives them to every drive
    services.led = [this](std::string_view query) {
      return led_response(bundle.device().leds(), bundle.core().time_ms(), query);
    };
    services.trace = &bundle.device().trace();
    router = std::make_unique<Router>(bundle.device(), services);
  }
  // The address fields exactly as server/drive_web.cpp fills them.
  void fill_as_the_server(Info& i) {
    i.ip = bundle.device().active_ip();
    i.mask = bundle.device().active_mask();
    i.bind = "127.0.0.1";
    i.http_port = 8080;
    i.faulhaber_port = 10002;
  }
  Response call(std::string method, std::string target, std::string body = "") {
    std::string type = body.empty() ? std::string() : std::string("application/json");
    Response out;
    int calls = 0;
    router->handle(make_request(std::move(method), std::move(target), std::move(type), std::move(body)),
                   [&](Response r) {
                     out = std::move(r);
                     ++calls;
                   });
    EXPECT_EQ(calls, 1);
    return out;
  }
  json status() { return json::parse(call("GET", "/api/v1/status").body); }

  mcemu::testing::DeviceFixture bundle;
  Services services;
  std::unique_ptr<Router> router;
};

std::optional<std::string> find_header(const Response& r, std::string_view name) {
  for (const auto& [k, v] : r.headers) {
    if (k == name) return v;
  }
  return std::nullopt;
}

TEST(FhStatus, SnapshotHasTheMcPartsAndNoneOfTheMovingCap) {
  FhFixture f;
  f.bundle.step(10);
  const json s = f.status();
  EXPECT_EQ(s["personality"], "faulhaber");
  EXPECT_EQ(s["state"], "SOD");
  EXPECT_EQ(s["stateName"], "Switch on disabled");
  EXPECT_EQ(s["led"], (json{{"color", "green"}, {"blink", true}}));
  EXPECT_EQ(s["basic"], (json{{"running", 0}, {"line", nullptr}, {"autostart", 0}}));
  for (const char* k : {"python", "refgo", "udp", "ts", "tpsr", "live", "virtualInputs", "mfrStatus"}) {
    EXPECT_FALSE(s.contains(k)) << k;
  }
  EXPECT_EQ(s["footer"]["state"], "Switch on disabled");
  EXPECT_EQ(s["footer"]["statwd"], "StatWd 0040h");
  EXPECT_EQ(s["footer"]["io"], "I........O..");
  EXPECT_EQ(s["seq"].get<int>() + 1, f.status()["seq"].get<int>());
}

TEST(FhStatus, InputsFaultAndBasicReachTheSnapshot) {
  FhFixture f;
  f.bundle.step(10);
  ASSERT_EQ(f.call("PUT", "/api/v1/faulhaber/inputs", R"({"levels": 5})").status, 200);
  EXPECT_EQ(f.status()["footer"]["io"], "I1.3.....O..");
  EXPECT_EQ(f.status()["digIn"], 5);

  ASSERT_EQ(f.call("PUT", "/api/v1/faulhaber/programs/2", ":Top\r\na = a + 1\r\nGOTO Top\r\n").status, 200);
  ASSERT_EQ(f.call("POST", "/api/v1/faulhaber/programs/2/start", "{}").status, 200);
  f.bundle.step(5);
  json s = f.status();
  EXPECT_EQ(s["basic"]["running"], 2);
  EXPECT_TRUE(s["basic"]["line"].is_number());
  EXPECT_EQ(s["footer"]["basic"], "BASIC RUN 2");

  ASSERT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "drive.inject", "cause": "stroke"})").status, 201);
  f.bundle.step(20);
  s = f.status();
  EXPECT_EQ(s["state"], "F");
  EXPECT_EQ(s["led"]["color"], "red");
  EXPECT_EQ(s["footer"]["state"], "Fault 8611h");
  EXPECT_EQ(s["lastError"]["text"], "8611h / following error");
  EXPECT_EQ(s["errorWord"], 2);
}

// The snapshot is cached until something it shows changes (issue 26); MC BASIC's state is outside
// the dictionary and drive time stands still under the manual clock, so a start and a stop must
// reach the next snapshot by themselves.
TEST(FhStatus, ProgramStartAndStopReachTheNextSnapshotWithoutAStep) {
  FhFixture f;
  f.bundle.step(10);
  ASSERT_EQ(f.call("PUT", "/api/v1/faulhaber/programs/2", ":Top\r\na = a + 1\r\nGOTO Top\r\n").status, 200);
  EXPECT_EQ(f.status()["basic"]["running"], 0);
  ASSERT_EQ(f.call("POST", "/api/v1/faulhaber/programs/2/start", "{}").status, 200);
  EXPECT_EQ(f.status()["basic"]["running"], 2);
  ASSERT_EQ(f.call("POST", "/api/v1/faulhaber/stop", "{}").status, 200);
  EXPECT_EQ(f.status()["basic"]["running"], 0);
}

TEST(FhPages, EmulatorPageFromItsOwnTemplateEverythingElseRedirected) {
  FhFixture f;
  f.bundle.step(10);
  const auto page = f.call("GET", "/emulator.html");
  ASSERT_EQ(page.status, 200);
  EXPECT_EQ(page.content_type, "text/html; charset=utf-8");
  EXPECT_EQ(page.body.find("{{"), std::string::npos) << "a placeholder was not filled";
  EXPECT_NE(page.body.find(R"(id="fh-basic")"), std::string::npos);
  EXPECT_NE(page.body.find(R"(<span id="ft-state">Switch on disabled</span>)"), std::string::npos);
  EXPECT_NE(page.body.find(R"(<span id="ft-statwd">StatWd 0040h</span>)"), std::string::npos);
  EXPECT_EQ(page.body.find("/clickrun.html"), std::string::npos) << "the menu shows only what the drive has";
  EXPECT_EQ(page.body.find("id=\"led-yellow\""), std::string::npos);
  EXPECT_EQ(f.call("HEAD", "/emulator.html").status, 200);

  for (const char* p :
       {"/", "/index.html", "/clickrun.html", "/servo.html", "/ioin.html", "/ioout.html", "/command.html",
        "/program.html", "/network.html", "/faulhaber.html", "/program.html?codeAct=3"}) {
    for (const char* m : {"GET", "HEAD"}) {
      const auto r = f.call(m, p);
      EXPECT_EQ(r.status, 302) << m << " " << p;
      EXPECT_EQ(find_header(r, "Location"), "/emulator.html") << m << " " << p;
    }
  }
  EXPECT_EQ(f.call("POST", "/program.html", "x").status, 404) << "no MovingCap upload endpoint";
  EXPECT_EQ(f.call("GET", "/nope.html").status, 404);
  EXPECT_EQ(f.call("GET", "/static/mcemu.css").status, 200);
  EXPECT_EQ(f.call("GET", "/static/js/pages/faulhaber.js").status, 200);
}

TEST(FhPages, TemplateKeysAreAllKnownForAFaulhaberDrive) {
  FhFixture f;
  f.bundle.step(10);
  PageContext ctx;
  ctx.info = f.router->info_json();
  ctx.status = f.status();
  const auto* tmpl = assets::find("/faulhaber.html");
  ASSERT_NE(tmpl, nullptr);
  EXPECT_TRUE(unknown_keys(tmpl->bytes, ctx, embedded_partials()).empty());
}

TEST(FhPages, EveryModelServesItsPageAndRefGoIsRefusedNotCrashed) {
  for (const char* model : {"FH_MC5004", "FH_MC5005", "FH_MC5010", "FH_MCS"}) {
    FhFixture f(model);
    f.bundle.step(5);
    EXPECT_EQ(f.call("GET", "/emulator.html").status, 200) << model;
    EXPECT_EQ(f.call("POST", "/api/v1/refgo", R"({"line": "TP"})").status, 503) << model;
  }
}

// GET /api/v1/info: a FAULHABER MC has no IP address of its own (no 5007h/5008h; it is reached
// over RS232), so "ip" and "mask" are left out; "bind" and "ports" say where mcemu listens for it.
// A MovingCap keeps both.
TEST(FhInfo, NoIpOrMaskTheListenersSayWhereTheDriveIs) {
  for (const char* model : {"FH_MC5004", "FH_MC5005", "FH_MC5010", "FH_MCS"}) {
    FhFixture f(model);
    const json info = f.router->info_json();
    EXPECT_FALSE(info.contains("ip")) << model << " " << info.dump();
    EXPECT_FALSE(info.contains("mask")) << model;
    EXPECT_EQ(info["bind"], "127.0.0.1") << model;
    EXPECT_EQ(info["ports"], (json{{"faulhaber", 10002}, {"http", 8080}})) << model;
    EXPECT_EQ(json::parse(f.call("GET", "/api/v1/info").body), info) << model;
  }
  mcemu::testing::DeviceFixture bundle("MC349");
  Services services;
  services.info = [&] {
    Info i;
    i.ip = bundle.device().active_ip();
    i.mask = bundle.device().active_mask();
    return i;
  };
  Router router(bundle.device(), services);
  const json info = router.info_json();
  EXPECT_EQ(info["ip"], "192.168.2.150");
  EXPECT_EQ(info["mask"], "255.255.255.0");
}

// GET /api/v1/led: a FAULHABER MC has no Morse-coded STATUS LED; the route answers its bicolour
// status LED (as the snapshot's "led"), never the MovingCap's Morse schedule.
TEST(FhLed, ApiLedAnswersTheStatusLedNotTheMorseSchedule) {
  FhFixture f;
  f.bundle.step(10);
  auto led = [&](const char* target = "/api/v1/led") {
    const Response r = f.call("GET", target);
    EXPECT_EQ(r.status, 200) << r.body;
    EXPECT_EQ(find_header(r, "Cache-Control"), "no-store");
    return json::parse(r.body);
  };
  EXPECT_EQ(led(), (json{{"timeMs", 10}, {"personality", "faulhaber"}, {"color", "green"}, {"blink", true}}));
  EXPECT_EQ(led()["color"], f.status()["led"]["color"]);
  EXPECT_EQ(led("/api/v1/led?fromMs=0&toMs=10"), led()) << "no edges to window";
  f.bundle.W(0x6040, 0, 0x06);
  f.bundle.W(0x6040, 0, 0x0F);
  f.bundle.step(2);
  EXPECT_EQ(led()["color"], "green");
  EXPECT_EQ(led()["blink"], false) << "Operation enabled: steady";
  ASSERT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "drive.inject", "cause": "stroke"})").status, 201);
  f.bundle.step(20);
  EXPECT_EQ(led()["color"], "red");
}

TEST(MovingCapPages, TheFaulhaberTemplateIsNotServed) {
  mcemu::testing::DeviceFixture bundle("MC349");
  Services services;
  Router router(bundle.device(), services);
  int status = 0;
  router.handle(make_request("GET", "/faulhaber.html"), [&](Response r) { status = r.status; });
  EXPECT_EQ(status, 404);
  router.handle(make_request("GET", "/emulator.html"), [&](Response r) { status = r.status; });
  EXPECT_EQ(status, 200);
  router.handle(make_request("GET", "/index.html"), [&](Response r) { status = r.status; });
  EXPECT_EQ(status, 200);
}

}  // namespace
}  // namespace mcemu::web::api
