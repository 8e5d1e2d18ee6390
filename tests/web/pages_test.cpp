// Server-side rendering of the pages (web.md §3.5, §4.2, §11 last paragraph: `curl` of every page
// shows the footer strings): the template language alone, then every embedded page through the
// router of a real drive.
#include "web/api/pages.hpp"

#include <gtest/gtest.h>

#include <map>
#include <regex>

#include "tests/web/api_fixture.hpp"
#include "web/assets/assets.hpp"

namespace mcemu::web::api {
namespace {

using nlohmann::json;
using testing::ApiFixture;

PageContext context() {
  PageContext c;
  c.info = json{{"displayName", "MovingCap turnTRACK 349 Eth"},
                {"deviceName", "MC349_ETH_RE"},
                {"model", "MC349"},
                {"ports", {{"http", 8080}}},
                {"scripting", {{"available", false}, {"engine", nullptr}}}};
  c.status = json{{"footer", {{"live", "MC Live OFF"}, {"statwd", "StatWd 0040h"}, {"io", "I1.........O...."}}},
                  {"led", {{"green", true}, {"yellow", false}}},
                  {"lastError", nullptr},
                  {"python", {{"state", "OFF"}, {"id", "(empty)"}, {"autostart", false}}},
                  {"temperatureC", nullptr}};
  c.object = [](std::uint16_t index, std::uint8_t sub) -> std::optional<json> {
    if (index == 0x6081 && sub == 0) return json(1000);
    if (index == 0x1002 && sub == 0) return json(0x40);
    if (index == 0x1008 && sub == 0) return json("MC349_ETH_RE");
    return std::nullopt;
  };
  return c;
}

std::map<std::string, std::string> partials_map{{"a", "[A {{info.model}} {{> b}}]"}, {"b", "B"}};
PartialLookup partials() {
  return [](std::string_view name) -> std::optional<std::string_view> {
    const auto it = partials_map.find(std::string(name));
    if (it == partials_map.end()) return std::nullopt;
    return it->second;
  };
}

TEST(PageTemplate, ValuesAreFilledAndEscaped) {
  auto c = context();
  c.info["displayName"] = "A <b>&\"'";
  EXPECT_EQ(render_page("<h1>{{info.displayName}}</h1>", c, partials()), "<h1>A &lt;b&gt;&amp;&quot;&#39;</h1>");
  EXPECT_EQ(render_page("{{ info.ports.http }}|{{status.footer.statwd}}", c, partials()), "8080|StatWd 0040h");
  EXPECT_EQ(render_page("{{status.lastError}} {{status.temperatureC}} {{info.scripting.available}}", c, partials()),
            "- - false");
  EXPECT_EQ(render_page("{{footer.io}} {{led.green}}{{led.yellow}} {{model.short}}", c, partials()),
            "I1.........O.... 10 MC349");
  EXPECT_EQ(render_page("{{lastError}}", c, partials()), "-");
  c.status["lastError"] = json{{"code", 0x7121}, {"text", "7121h / ERROR_STROKE"}};
  EXPECT_EQ(render_page("{{lastError}}", c, partials()), "7121h / ERROR_STROKE");
}

TEST(PageTemplate, ObjectsInDecimalHexAndText) {
  const auto c = context();
  EXPECT_EQ(render_page(R"(<input value="{{od.6081.00}}"> {{odh.1002.00}} {{od.1008.0}})", c, partials()),
            R"(<input value="1000"> 0040h MC349_ETH_RE)");
  EXPECT_EQ(render_page("[{{od.607A.00}}]", c, partials()), "[]") << "an object that cannot be read is empty";
}

TEST(PageTemplate, LiveFooterErrIsARedLinkWithTheSameText) {
  auto c = context();
  EXPECT_EQ(render_page("{{footer.live}}", c, partials()), "MC Live OFF");
  c.status["footer"]["live"] = "MC Live ERR 7121h";
  EXPECT_EQ(render_page("{{footer.live}}", c, partials()),
            R"(MC Live <a href="/index.html" class="err">ERR 7121h</a>)");
}

TEST(PageTemplate, UnknownKeysStayAsWrittenAndAreReported) {
  const auto c = context();
  EXPECT_EQ(render_page("x {{nope}} {{info.missing}} {{od.zz.00}} {{ y", c, partials()),
            "x {{nope}} {{info.missing}} {{od.zz.00}} {{ y");
  EXPECT_EQ(unknown_keys("{{nope}} {{info.model}} {{> missing}}", c, partials()),
            (std::vector<std::string>{"nope", "> missing"}));
}

TEST(PageTemplate, PartialsAreOneLevelDeep) {
  const auto c = context();
  EXPECT_EQ(render_page("<{{> a}}>", c, partials()), "<[A MC349 {{> b}}]>");
  EXPECT_EQ(unknown_keys("{{> a}}", c, partials()), (std::vector<std::string>{"> b"}));
}

TEST(PageTemplate, PageDataIsJsonSafeInsideAScriptElement) {
  auto c = context();
  c.info["deviceName"] = "</script><b>_ETH";
  c.model.input_pins = {1, 2, 3, 4};
  const auto text = render_page("{{page.data}}", c, partials());
  EXPECT_EQ(text.find('<'), std::string::npos) << text;
  const auto data = json::parse(text);
  EXPECT_EQ(data["shortName"], "</script><b>");
  EXPECT_EQ(data["inputPins"], json::array({1, 2, 3, 4}));
  EXPECT_EQ(data["linear"], false);
  EXPECT_EQ(data["accelerationUnit"], "1 unit = 100 motor rev/min²");
}

TEST(PageTemplate, CodePageWithAndWithoutEngine) {
  auto c = context();
  EXPECT_EQ(render_page("{{code.status}}|{{code.autoOn}}|{{code.autoOff}}|{{code.viewer}}", c, partials()),
            "OFF (empty)|ON|OFF [X]|");
  EXPECT_NE(render_page("{{code.engine}}", c, partials()).find("not available"), std::string::npos);
  ScriptView v;
  v.id = "demo <1>";
  v.state = "RUN";
  v.autostart = true;
  v.source = "#id demo\nprint('<x>')\n";
  c.script = v;
  c.info["scripting"] = json{{"available", true}, {"engine", "python3 3.11.2"}};
  EXPECT_EQ(render_page("{{code.status}}|{{code.autoOn}}|{{code.autoOff}}|{{code.viewer}}", c, partials()),
            "RUN demo &lt;1&gt;|ON [X]|OFF|#id demo\nprint(&#39;&lt;x&gt;&#39;)\n");
  EXPECT_EQ(render_page("{{code.engine}}", c, partials()), "Script engine: python3 3.11.2");
  // docs/security.md: without the sandbox the page says why (unavailable) or says so (unsafe)
  c.info["scripting"] = json{{"available", false}, {"engine", nullptr}, {"reason", "no sandbox <here>"}};
  EXPECT_EQ(render_page("{{code.engine}}", c, partials()),
            "The script engine is not available: no sandbox &lt;here&gt;.");
  c.info["scripting"] = json{{"available", true},
                             {"engine", "python3 3.11.2"},
                             {"sandbox", {{"active", false}, {"unsafe", true}, {"reason", "UNSAFE: no sandbox"}}}};
  EXPECT_EQ(render_page("{{code.engine}}", c, partials()), "Script engine: python3 3.11.2. UNSAFE: no sandbox.");
}

TEST(PageTemplate, Helpers) {
  EXPECT_EQ(short_model_name("MC349_ETH_AE"), "MC349");
  EXPECT_EQ(short_model_name("MCFLAT_ETH_RABBIT"), "MCFLAT");
  EXPECT_EQ(short_model_name("custom"), "custom");
  PageModel m;
  EXPECT_EQ(acceleration_unit_text(m), "1 unit = 100 motor rev/min²");
  m.rotary_accel_unit_num = 1;
  m.rotary_accel_unit_den = 7;
  EXPECT_EQ(acceleration_unit_text(m), "1 unit = 514.3 motor rev/min²");
  m.linear = true;
  EXPECT_EQ(acceleration_unit_text(m), "1 unit = 1000 user position units/s²");
}

// ---- every embedded page through the router of a real MC349

std::vector<std::string> embedded_pages() {
  std::vector<std::string> out;
  for (const auto& a : assets::all()) {
    // /faulhaber.html is the FAULHABER drive's Emulator page (faulhaber_pages_test.cpp), not a MovingCap page
    if (a.mime.substr(0, 9) == "text/html" && a.path.rfind("/static/", 0) != 0 && a.path != "/faulhaber.html") {
      out.emplace_back(a.path);
    }
  }
  return out;
}

TEST(Pages, EveryPageOfTheUrlMapIsEmbedded) {
  const auto pages = embedded_pages();
  for (const char* p : {"/index.html", "/clickrun.html", "/servo.html", "/ioin.html", "/ioout.html", "/command.html",
                        "/program.html", "/network.html", "/emulator.html"}) {
    EXPECT_NE(std::find(pages.begin(), pages.end(), p), pages.end()) << p;
  }
}

TEST(Pages, EveryPageRendersWithTheFooterStringsOfTheStatus) {
  ApiFixture f;
  f.step(10);
  const auto footer = f.status()["footer"];
  for (const auto& path : embedded_pages()) {
    const auto r = f.call("GET", path);
    ASSERT_EQ(r.status, 200) << path;
    EXPECT_EQ(r.content_type, "text/html; charset=utf-8");
    EXPECT_EQ(r.body.find("{{"), std::string::npos) << path << ": a placeholder was not filled";
    EXPECT_NE(r.body.find(R"(<nav id="menubar")"), std::string::npos) << path;
    EXPECT_NE(r.body.find(R"(id="led-green")"), std::string::npos) << path;
    for (const auto& [key, text] : footer.items()) {
      const std::string want = "<span id=\"ft-" + key + "\">" + text.get<std::string>() + "</span>";
      EXPECT_NE(r.body.find(want), std::string::npos) << path << " lacks " << want;
    }
    const auto* asset = assets::find(path);
    EXPECT_TRUE(
        unknown_keys(asset->bytes, PageContext{f.r().info_json(), f.status(), {}, {}, {}}, embedded_partials()).empty())
        << path;
  }
}

TEST(Pages, RenderedValuesFollowTheDrive) {
  ApiFixture f;
  f.services.info = [] {
    Info i;
    i.model = "MC349";
    i.device_name = "MC349_ETH_RE";
    return i;
  };
  f.make_router();
  f.step(10);
  ASSERT_EQ(f.call("PUT", "/api/v1/objects/6081/0", R"({"value": 1234})").status, 200);
  EXPECT_NE(f.call("GET", "/clickrun.html").body.find(R"(id="cr-vel" value="1234")"), std::string::npos);
  EXPECT_NE(f.call("GET", "/clickrun.html").body.find("<h1>MC349 Click &amp; Run</h1>"), std::string::npos);
  f.refgo("PWC");
  f.step(20);
  ASSERT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "drive.inject", "cause": "stroke"})").status, 201);
  f.step(20);
  const auto body = f.call("GET", "/").body;
  EXPECT_NE(body.find(R"(<span id="ft-live">MC Live <a href="/index.html" class="err">ERR 7121h</a></span>)"),
            std::string::npos);
  EXPECT_NE(body.find(R"(<span id="info-lasterror" class="mono">7121h / ERROR_STROKE</span>)"), std::string::npos);
  EXPECT_NE(f.call("HEAD", "/index.html").body.find("ERR 7121h"), std::string::npos) << "HEAD: GET's headers";
}

TEST(Pages, AnswersOfThePagesHookAreRenderedToo) {
  ApiFixture f;
  f.services.pages = [](const Request& r, const Respond& respond) {
    if (r.target != "/hook.html") return false;
    Response page;
    page.content_type = "text/html; charset=utf-8";
    page.body = "<p>{{footer.statwd}}</p>";
    respond(page);
    return true;
  };
  f.make_router();
  f.step(5);
  EXPECT_EQ(f.call("GET", "/hook.html").body, "<p>StatWd 0040h</p>");
  EXPECT_EQ(f.call("GET", "/static/mcemu.css").body.find("{{"), std::string::npos);
}

}  // namespace
}  // namespace mcemu::web::api
