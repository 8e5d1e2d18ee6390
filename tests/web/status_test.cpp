// The live footer strings of web.md §4.2, the error names of §5.1 and the status snapshot of §8.2
// (table-driven for the footer; a real MC349 stepped in simulated time for the snapshot).
#include "web/api/status.hpp"

#include <gtest/gtest.h>

#include "tests/web/api_fixture.hpp"
#include "web/api/http_util.hpp"

namespace mcemu::web::api {
namespace {

using nlohmann::json;
using testing::ApiFixture;

// ---- footer strings: the manual's examples and the rules around them ---------------------------

struct FooterCase {
  const char* name;
  FooterValues v;
  const char* field;  // which footer string
  const char* text;
};

std::string field_of(const Footer& f, std::string_view name) {
  if (name == "live") return f.live;
  if (name == "statwd") return f.statwd;
  if (name == "opmode") return f.opmode;
  if (name == "python") return f.python;
  if (name == "pos") return f.pos;
  if (name == "vel") return f.vel;
  if (name == "temp") return f.temp;
  return f.io;
}

FooterValues with(std::function<void(FooterValues&)> set) {
  FooterValues v;
  set(v);
  return v;
}

class FooterTable : public ::testing::TestWithParam<FooterCase> {};

TEST_P(FooterTable, ExactText) {
  const auto& c = GetParam();
  EXPECT_EQ(field_of(footer(c.v), c.field), c.text) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Manual, FooterTable,
    ::testing::Values(
        FooterCase{"pos long", with([](auto& v) { v.pos_user = 32, v.pos_inc = 29375; }), "pos",
                   "Pos 32 usr/ 29375 inc"},
        FooterCase{"pos short", with([](auto& v) { v.pos_user = 1520, v.pos_inc = 1520; }), "pos", "Pos 1520 inc"},
        FooterCase{"pos negative", with([](auto& v) { v.pos_user = -7, v.pos_inc = -29375; }), "pos",
                   "Pos -7 usr/ -29375 inc"},
        FooterCase{"vel long", with([](auto& v) { v.vel_user = 106, v.vel_rpm = 88; }), "vel", "Vel 106 usr/ 88 rpm"},
        FooterCase{"vel short", with([](auto& v) { v.vel_user = 2, v.vel_rpm = 2; }), "vel", "Vel 2 rpm"},
        FooterCase{"vel short negative", with([](auto& v) { v.vel_user = -2, v.vel_rpm = -2; }), "vel", "Vel -2 rpm"},
        FooterCase{"vel zero", FooterValues{}, "vel", "Vel 0 rpm"},
        FooterCase{"temp", with([](auto& v) { v.temperature_c = 46; }), "temp",
                   "Temp 46\xC2\xB0"
                   "C"},
        FooterCase{"no sensor", FooterValues{}, "temp", "Temp"},
        FooterCase{"io manual example", with([](auto& v) {
                     v.inputs = (1u << 16) | (1u << 17) | (1u << 19), v.outputs = (1u << 16) | (1u << 18);
                   }),
                   "io", "I12.4......O1.3."},
        FooterCase{"io IN10 is 0", with([](auto& v) { v.inputs = 1u << 25; }), "io", "I.........0O...."},
        FooterCase{"io all", with([](auto& v) { v.inputs = 0x03FF0000, v.outputs = 0x000F0000; }), "io",
                   "I1234567890O1234"},
        FooterCase{"io none, other bits ignored", with([](auto& v) { v.inputs = 0xFC00FFFF, v.outputs = 0xFFF0FFFF; }),
                   "io", "I..........O...."},
        FooterCase{"live off", FooterValues{}, "live", "MC Live OFF"},
        FooterCase{"live rdy", with([](auto& v) { v.ts = 1; }), "live", "MC Live RDY"},
        FooterCase{"live mov", with([](auto& v) { v.ts = 2; }), "live", "MC Live MOV"},
        FooterCase{"live err", with([](auto& v) { v.ts = 9, v.error_code = 0x7121; }), "live", "MC Live ERR 7121h"},
        FooterCase{"live err hex upper", with([](auto& v) { v.ts = 9, v.error_code = 0xFFF2; }), "live",
                   "MC Live ERR FFF2h"},
        FooterCase{"statwd", with([](auto& v) { v.statusword = 0x0427; }), "statwd", "StatWd 0427h"},
        FooterCase{"statwd sod", with([](auto& v) { v.statusword = 0x0040; }), "statwd", "StatWd 0040h"},
        FooterCase{"opmode", with([](auto& v) { v.op_mode_display = 1; }), "opmode", "OpMode 1"},
        FooterCase{"opmode signed", with([](auto& v) { v.op_mode_display = -1; }), "opmode", "OpMode -1"},
        FooterCase{"python off", FooterValues{}, "python", "Python OFF"},
        FooterCase{"python run", with([](auto& v) { v.python_state = "RUN"; }), "python", "Python RUN"},
        FooterCase{"python brk", with([](auto& v) { v.python_state = "BRK"; }), "python", "Python BRK"},
        FooterCase{"python run autostart", with([](auto& v) { v.python_state = "RUN", v.autostart = true; }), "python",
                   "Python RUN/A"}));

TEST(MotorRpm, RoundsHalfAwayFromZeroAndFollowsPolarity) {
  // MAN: gear 5 / feed 360, -2 rpm (-2184.5 inc/s) and 88 rpm
  EXPECT_EQ(motor_rpm(-2 * 65536 / 60.0, 65536, 1, false), -2);
  EXPECT_EQ(motor_rpm(88 * 65536 / 60.0, 65536, 1, false), 88);
  EXPECT_EQ(motor_rpm(2.5, 60, 1, false), 3);
  EXPECT_EQ(motor_rpm(-2.5, 60, 1, false), -3);
  EXPECT_EQ(motor_rpm(2.49, 60, 1, false), 2);
  EXPECT_EQ(motor_rpm(100 * 65536 / 60.0, 65536, 1, true), -100) << "607Eh bit 6 negates like 606Ch";
  EXPECT_EQ(motor_rpm(1000, 65536, 2, false), 2) << "608Fh.02 motor revolutions";
  EXPECT_EQ(motor_rpm(1000, 0, 1, false), 0) << "no division by zero";
  EXPECT_EQ(motor_rpm(1e300, 1, 1, false), INT32_MAX) << "saturates";
}

TEST(ErrorNames, TableOfWebMd51) {
  const std::vector<std::pair<std::uint16_t, std::string_view>> expected{
      {0x2220, "ERROR_OVER_CURRENT"}, {0x3211, "ERROR_OVER_VOLT"},     {0x3221, "ERROR_UNDER_VOLT"},
      {0x4210, "ERROR_OVER_TEMP"},    {0x4220, "ERROR_DERATING"},      {0x5200, "ERROR_ACK"},
      {0x7121, "ERROR_STROKE"},       {0x7510, "ERROR_COMMUNICATION"}, {0x8130, "ERROR_ABORT_CONNECTION"},
      {0xFFF1, "ERROR_SENSOR"},       {0xFFF2, "ERROR_HW_SW_ENABLE"},  {0xFFF4, "ERROR_EXT_TORQUE"},
      {0xFFF5, "ERROR_NEEDS_RESET"}};
  ASSERT_EQ(error_names().size(), expected.size());
  for (const auto& [code, name] : expected) EXPECT_EQ(error_name(code), name) << std::hex << code;
  EXPECT_EQ(error_name(0x1234), "UNKNOWN");
  EXPECT_EQ(error_name(0), "UNKNOWN");
  EXPECT_EQ(last_error_text(0x7121), "7121h / ERROR_STROKE");
  EXPECT_EQ(last_error_text(0x0042), "0042h / UNKNOWN");
}

TEST(StateAbbreviation, EveryState) {
  using core::PdsState;
  EXPECT_EQ(state_abbreviation(PdsState::not_ready_to_switch_on), "NRTSO");
  EXPECT_EQ(state_abbreviation(PdsState::switch_on_disabled), "SOD");
  EXPECT_EQ(state_abbreviation(PdsState::ready_to_switch_on), "RTSO");
  EXPECT_EQ(state_abbreviation(PdsState::switched_on), "SO");
  EXPECT_EQ(state_abbreviation(PdsState::operation_enabled), "OE");
  EXPECT_EQ(state_abbreviation(PdsState::quick_stop_active), "QSA");
  EXPECT_EQ(state_abbreviation(PdsState::fault_reaction_active), "FRA");
  EXPECT_EQ(state_abbreviation(PdsState::fault), "F");
}

// ---- the snapshot of a real drive ------------------------------------------------------------

TEST(StatusSnapshot, EveryFieldOfWebMd82) {
  ApiFixture f;
  f.step(10);
  const json s = f.status();
  for (const char* key :
       {"seq",           "timeMs",  "state",         "live",      "ts",        "tpsr",         "statusword",
        "controlword",   "opMode",  "opModeDisplay", "errorCode", "lastError", "mfrStatus",    "posUser",
        "posInc",        "velUser", "velRpm",        "targetPos", "current",   "temperatureC", "inputs",
        "virtualInputs", "outputs", "python",        "refgo",     "udp",       "led",          "footer"}) {
    EXPECT_TRUE(s.contains(key)) << key;
  }
  EXPECT_EQ(s["timeMs"], f.core.time_ms());
  EXPECT_EQ(s["state"], "SOD");
  EXPECT_EQ(s["live"], "OFF");
  EXPECT_EQ(s["statusword"], 0x0040);
  EXPECT_EQ(s["lastError"], nullptr) << "1003h is empty after power-up";
  EXPECT_EQ(s["python"], (json{{"state", "OFF"}, {"autostart", false}, {"id", "(empty)"}, {"line", 0}}));
  EXPECT_EQ(s["refgo"], (json{{"clients", 0},
                              {"attachMode", 0},
                              {"repeatWay", 0},
                              {"waitTimeMs", 0},
                              {"backAndForth", false},
                              {"jogTimerMs", nullptr}}));
  EXPECT_EQ(s["udp"], (json{{"listeners", 0}}));
  EXPECT_EQ(s["led"], (json{{"green", false}, {"yellow", false}}));
  EXPECT_EQ(s["footer"], (json{{"live", "MC Live OFF"},
                               {"statwd", "StatWd 0040h"},
                               {"opmode", "OpMode 0"},
                               {"python", "Python OFF"},
                               {"pos", "Pos 0 inc"},
                               {"vel", "Vel 0 rpm"},
                               {"temp", "Temp"},
                               {"io", "I..........O...."}}));
  EXPECT_EQ(s["temperatureC"], nullptr) << "MC349 has no temperature sensor (models.md)";
}

TEST(StatusSnapshot, SeqCountsEverySnapshot) {
  ApiFixture f;
  const auto first = f.status()["seq"].get<std::uint64_t>();
  const auto text = f.r().status_text();  // the WebSocket hub's call shares the counter
  EXPECT_EQ(json::parse(text)["seq"], first + 1);
  EXPECT_EQ(f.status()["seq"], first + 2);
}

// Issue 26: the body is built once per change and shared; every snapshot still has the next seq.
TEST(StatusSnapshot, BodyIsBuiltOnlyWhenSomethingItShowsChanged) {
  ApiFixture f;
  f.step(3);
  StatusSnapshots snapshots;
  const auto a = json::parse(snapshots.build(f.r().status_inputs()));
  const auto b = json::parse(snapshots.build(f.r().status_inputs()));
  EXPECT_EQ(snapshots.bodies_built(), 1u) << "nothing changed in between";
  EXPECT_EQ(b["seq"], a["seq"].get<std::uint64_t>() + 1);
  auto without_seq = [](json j) {
    j.erase("seq");
    return j;
  };
  EXPECT_EQ(without_seq(a), without_seq(b));
  // Drive time moves on: the snapshot has the new time, and the body is rebuilt only if a value
  // changed in the step (the generation says).
  const auto generation = f.r().status_inputs().od.generation();
  f.step();
  const bool values_changed = f.r().status_inputs().od.generation() != generation;
  const auto c = json::parse(snapshots.build(f.r().status_inputs()));
  EXPECT_EQ(snapshots.bodies_built(), values_changed ? 2u : 1u);
  EXPECT_EQ(c["timeMs"], a["timeMs"].get<std::uint64_t>() + 1);
  EXPECT_EQ(c["seq"], b["seq"].get<std::uint64_t>() + 1);
  EXPECT_EQ(json::parse(status_json(f.r().status_inputs(), c["seq"])), c) << "the same as a body built afresh";
  const auto built = snapshots.bodies_built();
  ASSERT_EQ(f.refgo("OW6083,0,1234")["ok"], true);  // a value changes, drive time does not
  const auto d = json::parse(snapshots.build(f.r().status_inputs()));
  EXPECT_EQ(snapshots.bodies_built(), built + 1);
  EXPECT_EQ(json::parse(status_json(f.r().status_inputs(), d["seq"])), d);
}

TEST(StatusSnapshot, FollowsTheDriveThroughRefGo) {
  ApiFixture f;
  f.step(10);
  ASSERT_EQ(f.refgo("PWC")["ok"], true);
  f.step(50);
  auto s = f.status();
  EXPECT_EQ(s["state"], "OE");
  EXPECT_EQ(s["footer"]["live"], "MC Live RDY");
  EXPECT_EQ(s["footer"]["statwd"], "StatWd " + h4(s["statusword"].get<std::uint32_t>()));
  EXPECT_EQ(s["footer"]["opmode"], "OpMode 1");
  ASSERT_EQ(f.refgo("G200000")["ok"], true);
  f.step(20);
  s = f.status();
  EXPECT_EQ(s["live"], "MOV");
  EXPECT_EQ(s["footer"]["live"], "MC Live MOV");
  EXPECT_EQ(s["targetPos"], 200000);
  EXPECT_NE(s["velRpm"], 0);
  EXPECT_EQ(s["footer"]["vel"], "Vel " + std::to_string(s["velRpm"].get<int>()) + " rpm")
      << "identity factor group: 606Ch is rpm, the short form";
  EXPECT_EQ(s["velUser"], s["velRpm"]);
  f.step(5000);
  s = f.status();
  EXPECT_EQ(s["footer"]["statwd"], "StatWd 0427h") << "target reached";
  EXPECT_EQ(s["footer"]["live"], "MC Live RDY");
  EXPECT_EQ(s["footer"]["pos"], "Pos " + std::to_string(s["posInc"].get<int>()) + " inc");
  f.refgo("RW500");
  f.refgo("WT250");
  s = f.status();
  EXPECT_EQ(s["refgo"]["repeatWay"], 500);
  EXPECT_EQ(s["refgo"]["waitTimeMs"], 250);
}

TEST(StatusSnapshot, FaultShowsErrAndLastError) {
  ApiFixture f;
  f.step(10);
  f.refgo("PWC");
  f.step(20);
  ASSERT_EQ(f.call("POST", "/api/v1/faults", R"({"kind": "drive.inject", "cause": "stroke"})").status, 201);
  f.step(20);
  const auto s = f.status();
  EXPECT_EQ(s["state"], "F");
  EXPECT_EQ(s["live"], "ERR");
  EXPECT_EQ(s["footer"]["live"], "MC Live ERR 7121h");
  EXPECT_EQ(s["errorCode"], 0x7121);
  EXPECT_EQ(s["lastError"], (json{{"code", 0x7121}, {"text", "7121h / ERROR_STROKE"}}));
}

TEST(StatusSnapshot, JogTimerAndBackAndForth) {
  ApiFixture f;
  f.step(10);
  f.refgo("PWC");
  f.step(10);
  f.refgo("JP500");
  f.step(100);
  auto s = f.status();
  EXPECT_EQ(s["refgo"]["jogTimerMs"], 400) << "time left of JP500 after 100 ms";
  f.refgo("SM");
  f.step(200);
  f.refgo("PWC");
  f.step(10);
  f.refgo("RR1000");
  f.step(5);
  s = f.status();
  EXPECT_EQ(s["refgo"]["backAndForth"], true);
  EXPECT_EQ(s["refgo"]["jogTimerMs"], nullptr);
}

TEST(StatusSnapshot, PlainValuesFromTheServer) {
  ApiFixture f;
  f.services.refgo_clients = [] { return 3; };
  f.services.udp_listeners = [] { return 2; };
  f.services.led_state = [] { return LedStatus{true, false}; };
  f.make_router();
  f.od.write(0x3500, 4, od::Value{std::int64_t{1}}, od::Origin::web);
  const auto s = f.status();
  EXPECT_EQ(s["refgo"]["clients"], 3);
  EXPECT_EQ(s["udp"]["listeners"], 2);
  EXPECT_EQ(s["led"], (json{{"green", true}, {"yellow", false}}));
  EXPECT_EQ(s["python"]["autostart"], true);
  EXPECT_EQ(s["footer"]["python"], "Python OFF/A");
}

TEST(StatusSnapshot, TemperatureOnAModelWithASensor) {
  ApiFixture f("MCN23");
  f.step(5);
  const auto s = f.status();
  ASSERT_TRUE(s["temperatureC"].is_number()) << s.dump();
  EXPECT_EQ(s["footer"]["temp"], "Temp " + std::to_string(s["temperatureC"].get<int>()) +
                                     "\xC2\xB0"
                                     "C");
}

TEST(StatusSnapshot, InputsInTheFooter) {
  ApiFixture f;
  f.step(2);
  f.od.write(0x3510, 1, od::Value{std::int64_t{(1 << 16) | (1 << 19)}}, od::Origin::web);
  f.step(2);
  EXPECT_EQ(f.status()["footer"]["io"], "I1..4......O....");
}

}  // namespace
}  // namespace mcemu::web::api
