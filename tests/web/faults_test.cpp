// Fault injection over the JSON API (web.md §9, slcan-canopen.md §11.3) through the router, on a
// real dictionary and drive core stepped in simulated time: every kind, its validation, count and
// durationMs, the journal, and the physical effect of the drive kinds.
#include "device/faults.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/web/api_fixture.hpp"

namespace mcemu::web::api {
namespace {

using device::SdoPhase;
using device::TransportFaults;
using device::TransportKind;

using nlohmann::json;
using testing::ApiFixture;

Response post_fault(ApiFixture& f, const std::string& body) { return f.call("POST", "/api/v1/faults", body); }

json listed(ApiFixture& f) { return f.get("/api/v1/faults")["faults"]; }

std::vector<core::Emcy> emcys(ApiFixture& f) {
  std::vector<core::Emcy> out;
  f.bundle.device().handle_events();
  for (const auto& e : f.bundle.events) {
    if (const auto* m = std::get_if<core::Emcy>(&e)) out.push_back(*m);
  }
  f.bundle.events.clear();
  return out;
}

// ---- every kind is accepted, listed and removable ---------------------------------------------

const std::vector<std::string> k_valid_bodies{
    R"({"kind": "drive.inject", "cause": "sensor_warning"})",
    R"({"kind": "drive.supply", "volts": 47.5})",
    R"({"kind": "drive.ambient", "celsius": 30})",
    R"({"kind": "drive.load", "value": 0.01})",
    R"({"kind": "drive.obstacle", "positionInc": 100000, "side": 1})",
    R"({"kind": "refgo.noReply"})",
    R"({"kind": "refgo.delay", "ms": 200})",
    R"({"kind": "udp.drop"})",
    R"({"kind": "http.error", "status": 500})",
    R"({"kind": "http.error", "status": 404, "path": "/servo.html"})",
    R"({"kind": "slcan.dropTx"})",
    R"({"kind": "slcan.dropTx", "cobId": "1B2h"})",
    R"({"kind": "slcan.delayTx", "ms": 50})",
    R"({"kind": "slcan.sdoAbort", "index": "1008h", "sub": 0, "code": "08000000h", "phase": "segment"})",
    R"({"kind": "slcan.sdoAbort", "index": 24641, "sub": "0", "code": 134217728})",
    R"({"kind": "slcan.sdoNoReply"})",
    R"({"kind": "slcan.sdoNoReply", "index": "0x6041"})",
    R"({"kind": "slcan.heartbeatStop"})",
    R"({"kind": "slcan.bel"})",
};

class ValidKind : public ::testing::TestWithParam<std::string> {};

TEST_P(ValidKind, CreatedListedAndRemoved) {
  ApiFixture f;
  f.step(5);
  const auto r = post_fault(f, GetParam());
  ASSERT_EQ(r.status, 201) << r.body;
  const json answer = f.json_of(r);
  EXPECT_EQ(answer["kind"], json::parse(GetParam())["kind"]);
  const std::string id = answer["id"];
  ASSERT_EQ(listed(f).size(), 1u);
  EXPECT_EQ(listed(f)[0]["id"], id);
  EXPECT_EQ(f.call("DELETE", "/api/v1/faults/" + id).status, 200);
  EXPECT_TRUE(listed(f).empty());
  EXPECT_TRUE(f.transport_faults().active().empty());
  EXPECT_EQ(f.call("DELETE", "/api/v1/faults/" + id).status, 404);
}

INSTANTIATE_TEST_SUITE_P(Bodies, ValidKind, ::testing::ValuesIn(k_valid_bodies));

// ---- validation: 400 naming the field, nothing injected --------------------------------------

struct BadBody {
  std::string body;
  std::string names;  // the message must contain this
};

class InvalidKind : public ::testing::TestWithParam<BadBody> {};

TEST_P(InvalidKind, Is400NamingTheFieldAndInjectsNothing) {
  ApiFixture f;
  const auto r = post_fault(f, GetParam().body);
  EXPECT_EQ(r.status, 400) << GetParam().body;
  const json j = json::parse(r.body, nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["error"]["code"], "syntax");
  EXPECT_NE(j["error"]["message"].get<std::string>().find(GetParam().names), std::string::npos)
      << j["error"]["message"];
  EXPECT_TRUE(listed(f).empty());
  EXPECT_TRUE(f.transport_faults().active().empty());
}

INSTANTIATE_TEST_SUITE_P(
    Bodies, InvalidKind,
    ::testing::Values(
        BadBody{"{", "JSON object"}, BadBody{"[]", "JSON object"}, BadBody{R"({"cause": "stroke"})", "kind"},
        BadBody{R"({"kind": 5})", "kind"}, BadBody{R"({"kind": "gremlins"})", "kind"},
        BadBody{R"({"kind": "drive.inject"})", "cause"}, BadBody{R"({"kind": "drive.inject", "cause": "x"})", "cause"},
        BadBody{R"({"kind": "drive.emcy"})", "code"}, BadBody{R"({"kind": "drive.emcy", "code": "12345h"})", "code"},
        BadBody{R"({"kind": "drive.supply"})", "volts"}, BadBody{R"({"kind": "drive.supply", "volts": "48"})", "volts"},
        BadBody{R"({"kind": "drive.supply", "volts": -1})", "volts"},
        BadBody{R"({"kind": "drive.supply", "volts": 1e400})", "JSON object"},
        BadBody{R"({"kind": "drive.ambient", "celsius": null})", "celsius"},
        BadBody{R"({"kind": "drive.load"})", "value"},
        BadBody{R"({"kind": "drive.obstacle", "positionInc": 5, "side": 2})", "side"},
        BadBody{R"({"kind": "drive.obstacle", "positionInc": 1.5, "side": 1})", "positionInc"},
        BadBody{R"({"kind": "drive.obstacle", "side": 1})", "positionInc"},
        BadBody{R"({"kind": "drive.load", "value": 1, "durationMs": 0})", "durationMs"},
        BadBody{R"({"kind": "drive.load", "value": 1, "durationMs": -5})", "durationMs"},
        BadBody{R"({"kind": "drive.load", "value": 1, "count": 0})", "count"},
        BadBody{R"({"kind": "refgo.noReply", "count": "3"})", "count"},
        BadBody{R"({"kind": "refgo.noReply", "ms": 3})", "ms"}, BadBody{R"({"kind": "refgo.delay"})", "ms"},
        BadBody{R"({"kind": "refgo.delay", "ms": 0})", "ms"}, BadBody{R"({"kind": "refgo.delay", "ms": 600001})", "ms"},
        BadBody{R"({"kind": "http.error"})", "status"}, BadBody{R"({"kind": "http.error", "status": 200})", "status"},
        BadBody{R"({"kind": "http.error", "status": 500, "path": "index.html"})", "path"},
        BadBody{R"({"kind": "http.error", "status": 500, "path": "/api/v1/info"})", "path"},
        BadBody{R"({"kind": "slcan.dropTx", "cobId": "zz"})", "cobId"},
        BadBody{R"({"kind": "slcan.dropTx", "cobId": 536870912})", "cobId"},
        BadBody{R"({"kind": "slcan.delayTx"})", "ms"},
        BadBody{R"({"kind": "slcan.sdoAbort", "sub": 0, "code": "08000000h"})", "index"},
        BadBody{R"({"kind": "slcan.sdoAbort", "index": "1008h", "code": "08000000h"})", "sub"},
        BadBody{R"({"kind": "slcan.sdoAbort", "index": "1008h", "sub": 256, "code": "08000000h"})", "sub"},
        BadBody{R"({"kind": "slcan.sdoAbort", "index": "1008h", "sub": 0})", "code"},
        BadBody{R"({"kind": "slcan.sdoAbort", "index": "1008h", "sub": 0, "code": 0})", "code"},
        BadBody{R"({"kind": "slcan.sdoAbort", "index": "1008h", "sub": 0, "code": "08000000h", "phase": "x"})",
                "phase"},
        BadBody{R"({"kind": "slcan.sdoNoReply", "index": "10000h"})", "index"},
        BadBody{R"({"kind": "slcan.rawTx"})", "text"}, BadBody{R"({"kind": "slcan.rawTx", "text": ""})", "text"},
        BadBody{R"({"kind": "slcan.rawTx", "text": "t123\n"})", "text"},
        BadBody{R"({"kind": "slcan.rawTx", "text": "caf\u00e9"})", "text"},
        BadBody{R"({"kind": "slcan.bel", "cobId": 5})", "cobId"}));

TEST(FaultInjection, EmptyPostBodyIsAnEmptyObject) {
  ApiFixture f;
  const auto r = post_fault(f, "");
  EXPECT_EQ(r.status, 400);
  EXPECT_NE(r.body.find("kind"), std::string::npos) << "parsed as {} (web.md §1.3), which lacks kind";
}

// ---- durationMs on every kind (drive time), with the undo of the drive kinds ------------------

class Duration : public ::testing::TestWithParam<std::string> {};

TEST_P(Duration, RemovesItselfAfterThatMuchDriveTime) {
  ApiFixture f;
  f.step(5);
  json body = json::parse(GetParam());
  body["durationMs"] = 30;
  ASSERT_EQ(post_fault(f, body.dump()).status, 201);
  f.step(29);
  EXPECT_EQ(listed(f).size(), 1u);
  EXPECT_EQ(listed(f)[0]["expiresAtMs"], f.core.time_ms() + 1);
  f.step(1);
  EXPECT_TRUE(listed(f).empty());
  EXPECT_TRUE(f.transport_faults().active().empty());
}

INSTANTIATE_TEST_SUITE_P(Bodies, Duration, ::testing::ValuesIn(k_valid_bodies));

TEST(FaultInjection, DurationUndoesTheDriveKinds) {
  ApiFixture f;
  f.step(5);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.supply", "volts": 30, "durationMs": 10})").status, 201);
  f.step(2);
  EXPECT_EQ(f.core.supply_voltage(), 30);
  f.step(10);
  EXPECT_EQ(f.core.supply_voltage(), f.core.plant_params().supply_nominal_v);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.inject", "cause": "sensor", "durationMs": 10})").status, 201);
  EXPECT_TRUE(f.core.injected(core::FaultCause::sensor));
  f.step(10);
  EXPECT_FALSE(f.core.injected(core::FaultCause::sensor));
}

TEST(FaultInjection, DurationSurvivesAPowerOn) {
  ApiFixture f;
  f.step(1000);
  ASSERT_EQ(post_fault(f, R"({"kind": "udp.drop", "durationMs": 100})").status, 201);
  f.step(40);
  f.core.power_on();  // drive time restarts at 0
  f.step(59);
  EXPECT_EQ(listed(f).size(), 1u) << "60 ms left after the power on";
  f.step(1);
  EXPECT_TRUE(listed(f).empty());
}

// ---- count on every kind ------------------------------------------------------------------------

// One occurrence of a transport kind, as its adapter would ask.
struct CountCase {
  std::string body;
  std::function<bool(TransportFaults&)> occur;
};

class Count : public ::testing::TestWithParam<CountCase> {};

TEST_P(Count, TransportKindRemovesItselfAfterCountOccurrences) {
  ApiFixture f;
  json body = json::parse(GetParam().body);
  body["count"] = 2;
  ASSERT_EQ(post_fault(f, body.dump()).status, 201);
  auto& t = f.transport_faults();
  EXPECT_TRUE(GetParam().occur(t));
  EXPECT_EQ(listed(f)[0]["remaining"], 1);
  EXPECT_TRUE(GetParam().occur(t));
  EXPECT_TRUE(listed(f).empty()) << "removed after the second occurrence";
  EXPECT_FALSE(GetParam().occur(t));
  const auto events = f.api_events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back(), "fault f1 removed (count)");
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, Count,
    ::testing::Values(
        CountCase{R"({"kind": "refgo.noReply"})", [](TransportFaults& tf) { return tf.take_refgo_no_reply(); }},
        CountCase{R"({"kind": "refgo.delay", "ms": 5})", [](TransportFaults& tf) { return tf.refgo_delay_ms() == 5u; }},
        CountCase{R"({"kind": "udp.drop"})", [](TransportFaults& tf) { return tf.take_udp_drop(); }},
        CountCase{R"({"kind": "http.error", "status": 503})",
                  [](TransportFaults& tf) { return tf.take_http_error("/index.html") == 503; }},
        CountCase{R"({"kind": "slcan.dropTx", "cobId": 434})",
                  [](TransportFaults& tf) { return tf.slcan_drop(0x1B2); }},
        CountCase{R"({"kind": "slcan.delayTx", "ms": 7})",
                  [](TransportFaults& tf) { return tf.slcan_delay_ms() == 7u; }},
        CountCase{R"({"kind": "slcan.sdoAbort", "index": "6041h", "sub": 0, "code": "06010002h"})",
                  [](TransportFaults& tf) {
                    const auto p = tf.slcan_sdo_abort(0x6041, 0, SdoPhase::initiate);
                    return p && p->code == 0x06010002u;
                  }},
        CountCase{R"({"kind": "slcan.sdoNoReply"})", [](TransportFaults& tf) { return tf.take_sdo_no_reply(0x1000); }},
        CountCase{R"({"kind": "slcan.heartbeatStop"})", [](TransportFaults& tf) { return tf.take_heartbeat_stop(); }},
        CountCase{R"({"kind": "slcan.bel"})", [](TransportFaults& tf) { return tf.take_slcan_bel(); }}));

// slcan-canopen.md §11.3 says "the next matching SDO transfer": without a count, one transfer.
TEST(FaultInjection, SdoAbortWithoutCountAbortsOneTransfer) {
  ApiFixture f;
  ASSERT_EQ(post_fault(f, R"({"kind": "slcan.sdoAbort", "index": "6041h", "sub": 0, "code": "06010002h"})").status,
            201);
  EXPECT_EQ(listed(f)[0]["remaining"], 1);
  auto& t = f.transport_faults();
  EXPECT_TRUE(t.slcan_sdo_abort(0x6041, 0, SdoPhase::initiate));
  EXPECT_FALSE(t.slcan_sdo_abort(0x6041, 0, SdoPhase::initiate));
  EXPECT_TRUE(listed(f).empty());
}

TEST(FaultInjection, CountOfADriveKindCountsTheFaultsItRaises) {
  ApiFixture f;
  f.step(5);
  f.refgo("PWC");
  f.step(10);
  // Brown-out once: the injection removes itself (supply back to nominal) after the first fault.
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.supply", "volts": 10, "count": 1})").status, 201);
  f.step(20);
  EXPECT_EQ(f.n(0x603F, 0), 0x3221);
  EXPECT_TRUE(listed(f).empty());
  EXPECT_EQ(f.core.supply_voltage(), f.core.plant_params().supply_nominal_v);
  f.od.write(0x6040, 0, od::Value{std::int64_t{0x80}}, od::Origin::web);
  f.step(20);
  EXPECT_EQ(f.n(0x6041, 0) & 0x4F, 0x40) << "the fault reset succeeds: the condition is gone";
}

TEST(FaultInjection, CountOfDriveInjectCountsItsOwnCauseOnly) {
  ApiFixture f;
  f.step(5);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.inject", "cause": "sensor", "count": 1})").status, 201);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.inject", "cause": "over_current", "count": 2})").status, 201);
  f.step(5);
  const auto l = listed(f);
  ASSERT_EQ(l.size(), 1u) << l.dump();
  EXPECT_EQ(l[0]["cause"], "over_current");
  EXPECT_EQ(l[0]["remaining"], 1) << "its own fault was raised once";
  EXPECT_FALSE(f.core.injected(core::FaultCause::sensor)) << "cleared on removal";
}

// ---- one-shot kinds ---------------------------------------------------------------------------

TEST(FaultInjection, EmcyOfACauseRaisesItOnce) {
  ApiFixture f;
  f.step(5);
  emcys(f);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.emcy", "code": "4210h"})").status, 201);
  f.step(3);
  EXPECT_EQ(f.n(0x603F, 0), 0x4210);
  EXPECT_TRUE(listed(f).empty()) << "removed itself after one step";
  const auto e = emcys(f);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].code, 0x4210);
}

TEST(FaultInjection, EmcyOfAnyOtherCodeSendsOneMessageOnly) {
  ApiFixture f;
  f.step(5);
  emcys(f);
  const auto mfr = f.n(0x1002, 0);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.emcy", "code": "1234h"})").status, 201);
  f.step(3);
  const auto e = emcys(f);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].bytes(), (std::array<std::uint8_t, 8>{0x34, 0x12, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(f.n(0x603F, 0), 0) << "no fault, 603Fh unchanged (web.md §9)";
  EXPECT_EQ(f.n(0x1002, 0), mfr);
  EXPECT_EQ(f.n(0x1003, 0), 0);
  EXPECT_TRUE(listed(f).empty());
}

TEST(FaultInjection, DisconnectAndRawTxAreQueuedForTheServer) {
  ApiFixture f;
  int notified = 0;
  f.transport_faults().set_action_listener([&] { ++notified; });
  ASSERT_EQ(post_fault(f, R"({"kind": "refgo.disconnect"})").status, 201);
  ASSERT_EQ(post_fault(f, R"({"kind": "slcan.disconnect"})").status, 201);
  ASSERT_EQ(post_fault(f, R"({"kind": "slcan.rawTx", "text": "t12\r"})").status, 201);
  EXPECT_EQ(notified, 3);
  EXPECT_EQ(listed(f).size(), 3u) << "listed until performed";
  const auto actions = f.transport_faults().drain_actions();
  ASSERT_EQ(actions.size(), 3u);
  EXPECT_EQ(actions[0].kind, TransportKind::refgo_disconnect);
  EXPECT_EQ(actions[1].kind, TransportKind::slcan_disconnect);
  EXPECT_EQ(actions[2].text, "t12\r");
  EXPECT_TRUE(listed(f).empty());
}

TEST(FaultInjection, ScriptKillNeedsAScriptEngine) {
  ApiFixture f;
  const auto r = post_fault(f, R"({"kind": "script.kill"})");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(f.json_of(r)["error"]["code"], "unavailable");
  EXPECT_EQ(f.json_of(r)["error"]["message"], "script engine not available in this version");
}

// ---- journal: trace channel api and UDP notes --------------------------------------------------

TEST(FaultInjection, EveryInjectionAndRemovalIsJournaled) {
  ApiFixture f;
  std::vector<std::string> notes;
  f.services.note = [&](const std::string& text) { notes.push_back(text); };
  f.make_router();
  ASSERT_EQ(post_fault(f, R"({"kind": "udp.drop"})").status, 201);
  ASSERT_EQ(f.call("DELETE", "/api/v1/faults/f1").status, 200);
  EXPECT_TRUE(notes.empty()) << "udpEmulatorNotes is off";
  ASSERT_EQ(f.call("PUT", "/api/v1/settings", R"({"udpEmulatorNotes": true})").status, 200);
  ASSERT_EQ(post_fault(f, R"({"kind": "slcan.bel", "durationMs": 5})").status, 201);
  f.step(5);
  ASSERT_EQ(post_fault(f, R"({"kind": "drive.load", "value": 0.01})").status, 201);
  ASSERT_EQ(f.call("DELETE", "/api/v1/faults").status, 200);
  const auto events = f.api_events();
  const std::vector<std::string> faults_only = [&] {
    std::vector<std::string> out;
    for (const auto& e : events) {
      if (e.rfind("fault ", 0) == 0) out.push_back(e);
    }
    return out;
  }();
  EXPECT_EQ(faults_only, (std::vector<std::string>{
                             R"(fault f1 added: {"kind":"udp.drop"})", "fault f1 removed (api)",
                             R"(fault f2 added: {"durationMs":5,"kind":"slcan.bel"})", "fault f2 removed (duration)",
                             R"(fault f3 added: {"kind":"drive.load","value":0.01})", "fault f3 removed (all)"}));
  EXPECT_EQ(notes,
            (std::vector<std::string>{"api settings {\"udpEmulatorNotes\":true}", "fault injection f2 slcan.bel added",
                                      "fault injection f2 removed (duration)", "fault injection f3 drive.load added",
                                      "fault injection f3 removed (all)"}));
}

// ---- http.error applies to pages, not to /api/ ---------------------------------------------------

TEST(FaultInjection, HttpErrorAnswersMatchingPageRequests) {
  ApiFixture f;
  int pages = 0;
  f.services.pages = [&](const Request&, const Respond& respond) {
    ++pages;
    Response r;
    r.content_type = "text/html; charset=utf-8";
    r.body = "<html>page</html>";
    respond(r);
    return true;
  };
  f.make_router();
  ASSERT_EQ(post_fault(f, R"({"kind": "http.error", "status": 503, "path": "/servo", "count": 1})").status, 201);
  EXPECT_EQ(f.call("GET", "/index.html").status, 200) << "other path";
  EXPECT_EQ(f.call("GET", "/api/v1/info").status, 200) << "never the API";
  const auto r = f.call("GET", "/servo.html");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(f.call("GET", "/servo.html").status, 200) << "count 1 used";
  EXPECT_EQ(pages, 2);
}

// ---- the physical effect of the drive kinds (review: they could be no-ops with tests green) ----

// Under-voltage 3221h from a low supply: the monitor sees the injected voltage.
TEST(DriveKindEffect, SupplyLowGivesUnderVoltageFault) {
  for (const double volts : {48.0, 10.0}) {
    ApiFixture f;
    f.step(5);
    f.refgo("PWC");
    f.step(10);
    ASSERT_EQ(f.status()["state"], "OE");
    ASSERT_EQ(post_fault(f, json{{"kind", "drive.supply"}, {"volts", volts}}.dump()).status, 201);
    f.step(20);
    if (volts < 18) {
      EXPECT_EQ(f.status()["state"], "F");
      EXPECT_EQ(f.n(0x603F, 0), 0x3221);
      EXPECT_EQ(f.n(0x1002, 0) & 0x2, 0x2) << "1002h bit 1 under_voltage";
    } else {
      EXPECT_EQ(f.status()["state"], "OE") << "nominal supply: no fault";
    }
  }
}

// 3401h.0Ah follows the ambient temperature (thermal model, tau 900 s on MCN23).
TEST(DriveKindEffect, AmbientMovesTheTemperatureObject) {
  ApiFixture plain("MCN23");
  ApiFixture hot("MCN23");
  ASSERT_EQ(post_fault(hot, R"({"kind": "drive.ambient", "celsius": 85})").status, 201);
  plain.step(60000);
  hot.step(60000);
  const auto t_plain = plain.n(0x3401, 0x0A);
  const auto t_hot = hot.n(0x3401, 0x0A);
  EXPECT_GE(t_hot, t_plain + 3) << "60 s at 85 °C ambient warm the drive";
  // Removal gives the drive its normal ambient back: it cools down again.
  const double before = hot.core.temperature_c();
  ASSERT_EQ(hot.call("DELETE", "/api/v1/faults").status, 200);
  hot.step(10000);
  EXPECT_LT(hot.core.temperature_c(), before) << "it cools again (it would still warm at 85 °C)";
}

// A move towards an obstacle stops at it; without the obstacle the same move reaches its target.
TEST(DriveKindEffect, ObstacleBlocksTheMove) {
  for (const bool obstacle : {false, true}) {
    ApiFixture f;
    f.step(5);
    f.refgo("PWC");
    f.step(10);
    const auto start = f.core.raw_position_inc();
    if (obstacle) {
      ASSERT_EQ(
          post_fault(f, json{{"kind", "drive.obstacle"}, {"positionInc", start + 20000}, {"side", 1}}.dump()).status,
          201);
    }
    f.refgo("G" + std::to_string(f.n(0x6064, 0) + 100000));
    f.step(5000);
    const auto moved = f.core.raw_position_inc() - start;
    if (obstacle) {
      EXPECT_LE(moved, 20000 + 50) << "stopped at the obstacle";
      EXPECT_GE(moved, 20000 - 2000) << "it did get there";
    } else {
      EXPECT_NEAR(static_cast<double>(moved), 100000.0, 50.0) << "target reached";
    }
  }
}

// An external load needs holding current: 6078h follows the load while the position is held.
TEST(DriveKindEffect, LoadNeedsHoldingCurrent) {
  std::int64_t current[2] = {0, 0};
  for (const int loaded : {0, 1}) {
    ApiFixture f;
    f.step(5);
    f.refgo("PWC");
    f.step(10);
    if (loaded) {
      ASSERT_EQ(post_fault(f, R"({"kind": "drive.load", "value": 0.05})").status, 201);
    }
    f.step(500);
    current[loaded] = std::llabs(f.n(0x6078, 0));
  }
  EXPECT_LE(current[0], 20) << "no load: almost no current";
  EXPECT_GE(current[1], current[0] + 50) << "0.05 N·m of load shows in 6078h";
}

}  // namespace
}  // namespace mcemu::web::api
