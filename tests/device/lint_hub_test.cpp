// The master lint in the bundle (device/lint_hub.hpp): every producer feeds the engine what the
// drive really shows — dictionary writes with their connection, core events, power on, CAN frames
// and NMT states, FAULHABER and line-session requests and replies, MC BASIC — and the findings reach
// the trace channel lint, the counts and (error level) the UDP notes. The configuration: the "lint"
// section, --lint and --clock manual.
#include "device/lint_hub.hpp"

#include <gtest/gtest.h>

#include "device/config_error.hpp"
#include "lint/config.hpp"
#include "protocols/faulhaber/frame.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::device {
namespace {

using lint::RuleId;
using testing::DeviceFixture;
using testing::MemoryStorage;

std::uint64_t count(const Device& d, RuleId id) { return d.lint().engine().counts(id).occurrences; }

std::vector<trace::Event> lint_trace(Device& d) {
  trace::Ring::Query q;
  q.channels = trace::ChannelSet::none();
  q.channels.add(trace::Channel::lint);
  return d.trace().query(q).events;
}

// A bundle built from a Setup (the --lint and --clock manual inputs the fixture does not take).
struct Built {
  MemoryStorage storage;
  std::unique_ptr<Device> device;
  explicit Built(Setup setup) {
    Environment env;
    env.storage = &storage;
    device = std::make_unique<Device>(std::move(setup), std::move(env));
  }
};

Setup setup_with(nlohmann::json config, std::optional<lint::Mode> mode = std::nullopt, bool manual = false) {
  Setup s;
  s.config = std::move(config);
  s.lint_mode = mode;
  s.manual_clock = manual;
  return s;
}

TEST(LintHub, AWriteInAServedScopeIsJudgedAndTraced) {
  DeviceFixture d;
  d.step(10);  // Switch on disabled
  {
    const auto scope = d.device().lint().serve(7);
    d.W(0x6040, 0, 0x0F, od::Origin::web);  // Enable operation from Switch on disabled: ignored
  }
  d.W(0x6040, 0, 0x0F, od::Origin::sdo);  // again, outside any scope
  EXPECT_EQ(count(d.device(), RuleId::cia402_command_ignored), 2U);
  const auto events = lint_trace(d.device());
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0].conn, 7U);
  EXPECT_EQ(events[1].conn, 0U);
  EXPECT_NE(events[0].text.find("cia402.command_ignored warn: controlword 0x000F"), std::string::npos);
  EXPECT_TRUE(d.notes.empty());  // warn level: no UDP note
}

TEST(LintHub, ACarefulMasterAndTheHelpersAreQuiet) {
  DeviceFixture d;
  d.step(10);
  for (std::int64_t cw : {0x06, 0x07, 0x0F}) d.W(0x6040, 0, cw, od::Origin::web);
  d.W(0x6040, 0, 0x06, od::Origin::web);
  d.W(0x6040, 0, 0x00, od::Origin::web);
  // the RefGo helpers step through the states themselves (drive-core.md §12): no finding
  EXPECT_TRUE(d.refgo().execute("PWC", {}).has_value());
  EXPECT_TRUE(d.refgo().execute("G1000", {}).has_value());
  d.step(3000);
  EXPECT_EQ(d.device().lint().engine().total(lint::Severity::warn), 0U);
  EXPECT_TRUE(lint_trace(d.device()).empty());
}

TEST(LintHub, ErrorLevelFindingsAreUdpNotes) {
  DeviceFixture d("MC349", nlohmann::json{{"lint", {{"rules", {{"cia402.command_ignored", "error"}}}}}});
  d.step(10);
  d.W(0x6040, 0, 0x07, od::Origin::web);
  ASSERT_EQ(d.notes.size(), 1U);
  EXPECT_EQ(d.notes[0].rfind("lint cia402.command_ignored error: controlword 0x0007", 0), 0U) << d.notes[0];
  EXPECT_EQ(d.device().lint().engine().failing(), 1U);
}

TEST(LintHub, ModeOffInstallsNothing) {
  DeviceFixture d("MC349", nlohmann::json{{"lint", {{"mode", "off"}}}});
  d.step(10);
  EXPECT_FALSE(d.device().lint().active());
  d.W(0x6040, 0, 0x0F, od::Origin::web);
  EXPECT_EQ(count(d.device(), RuleId::cia402_command_ignored), 0U);
  auto s = d.device().lint().wrap(d.device().canopen()->make_session(), 3);
  s->receive("t00020232\r");  // stop, then an SDO request: would be canopen.sdo_while_stopped
  s->receive("t63284041600000000000\r");
  EXPECT_EQ(count(d.device(), RuleId::canopen_sdo_while_stopped), 0U);
}

TEST(LintHub, CommandLineModeAndManualClock) {
  const auto timing_on = [](const Built& b) { return b.device->lint().engine().config().timing; };
  const auto mode = [](const Built& b) { return b.device->lint().engine().config().mode; };
  Built plain(setup_with(nlohmann::json::object()));
  EXPECT_EQ(mode(plain), lint::Mode::warn);
  EXPECT_TRUE(timing_on(plain));
  Built strict(setup_with(nlohmann::json{{"lint", {{"mode", "off"}}}}, lint::Mode::strict));
  EXPECT_EQ(mode(strict), lint::Mode::strict);  // --lint wins over the section
  Built manual(setup_with(nlohmann::json::object(), std::nullopt, true));
  EXPECT_FALSE(timing_on(manual));  // --clock manual: drive time stands still between requests
  Built chosen(setup_with(nlohmann::json{{"lint", {{"timing", true}}}}, std::nullopt, true));
  EXPECT_TRUE(timing_on(chosen));  // the section's own choice stays
  const auto bad_rule = nlohmann::json{{"lint", {{"rules", {{"cia402.nope", "warn"}}}}}};
  EXPECT_THROW(Built{setup_with(bad_rule)}, ConfigError);
  const auto not_a_section = nlohmann::json{{"lint", "strict"}};
  EXPECT_THROW(Built{setup_with(not_a_section)}, ConfigError);
}

TEST(LintHub, CanopenFramesAndNmtStates) {
  DeviceFixture d;
  d.device().power_up_network();
  auto s = d.device().lint().wrap(d.device().canopen()->make_session(), 4);
  s->receive("t00020232\r");              // NMT stop
  s->receive("t63284041600000000000\r");  // SDO to a STOPPED node
  s->receive("t00020132\r");              // start
  s->receive("t63284041600000000000\r");  // answered: no overlap with the next
  s->receive("t63284041600000000000\r");
  s->receive("t23220F00\r");  // RPDO1 (6040h) with Enable operation from Switch on disabled
  EXPECT_EQ(count(d.device(), RuleId::canopen_sdo_while_stopped), 1U);
  EXPECT_EQ(count(d.device(), RuleId::canopen_sdo_overlap), 0U);
  EXPECT_EQ(count(d.device(), RuleId::canopen_motion_without_guarding), 1U);
  EXPECT_EQ(count(d.device(), RuleId::cia402_command_ignored), 1U);
  for (const auto& e : lint_trace(d.device())) EXPECT_EQ(e.conn, 4U) << e.text;
  s->receive("t00028232\r");  // reset communication: INITIALISING until the boot-up
  s->receive("t63284041600000000000\r");
  EXPECT_EQ(count(d.device(), RuleId::canopen_traffic_before_bootup), 1U);
}

TEST(LintHub, LineSessionsAreReadsAndCloseTheirSlot) {
  DeviceFixture d;
  auto& hub = d.device().lint();
  struct Inner final : line::StreamSession {
    LintHub& hub;
    explicit Inner(LintHub& h) : hub(h) {}
    void receive(std::string_view bytes) override {
      for (char c : bytes) {
        if (c == '\r') hub.request(lint::Link::refgo, hub.serving(), true);
      }
    }
    std::string take_output() override { return {}; }
    void peer_closed() override {}
    bool finished() const override { return false; }
  };
  auto s = hub.wrap(std::make_unique<Inner>(hub), 9);
  s->receive("TP\r");
  hub.reply(lint::Link::refgo, 9, lint::ReplyKind::response);
  s->receive("TP\rTS\r");  // two requests of one read: the second was sent before the first reply
  EXPECT_EQ(count(d.device(), RuleId::refgo_request_before_reply), 1U);
  s.reset();  // ConnectionClosed frees the slot: a new request is no longer behind the old ones
  EXPECT_EQ(hub.serving(), 0U);
  auto t = hub.wrap(std::make_unique<Inner>(hub), 9);
  d.step(100);
  t->receive("TP\r");
  EXPECT_EQ(count(d.device(), RuleId::refgo_request_before_reply), 1U);
}

std::string frame(std::uint8_t command, std::vector<std::uint8_t> data) {
  const auto bytes = faulhaber::encode(faulhaber::Frame{1, command, std::move(data)});
  return std::string(bytes.begin(), bytes.end());
}

TEST(LintHub, FaulhaberRequestsRepliesAndNotifications) {
  DeviceFixture d("FH_MC5005");
  d.device().power_up_network();
  d.step(10);  // Switch on disabled
  std::vector<std::uint8_t> commands;
  auto s = d.device().lint().wrap(d.device().faulhaber_port()->make_session(d.device().lint().faulhaber_trace(
                                      5, [&](const faulhaber::TraceEvent& e) { commands.push_back(e.command); })),
                                  5);
  s->take_output();
  s->receive(frame(0x04, {0x06, 0x00}));  // Shutdown: response, then the statusword notification
  s->take_output();
  d.step(10);
  s->receive(frame(0x01, {0x41, 0x60, 0x00}));  // a careful host waited for both
  s->take_output();
  EXPECT_EQ(d.device().lint().engine().total(lint::Severity::warn), 0U);
  d.step(10);
  // the next controlword write and a read in the same read: the read races the notification
  s->receive(frame(0x04, {0x07, 0x00}) + frame(0x01, {0x41, 0x60, 0x00}));
  EXPECT_EQ(count(d.device(), RuleId::faulhaber_request_before_reply), 1U);
  EXPECT_EQ(count(d.device(), RuleId::faulhaber_request_before_notification), 1U);
  EXPECT_EQ(d.device().lint().engine().total(lint::Severity::warn), 2U);
  EXPECT_FALSE(commands.empty());  // the wrapped trace still gets every event
}

TEST(LintHub, BasicBusyLoopAndSaveInALoop) {
  DeviceFixture d("FH_MC5005");
  ASSERT_EQ(d.device().upload_program(1, ":l\na = a + 1\nGOTO l\n"), basic::Programs::Upload::ok);
  ASSERT_EQ(d.device().basic()->start(1), basic::Programs::Start::ok);
  d.step(99);  // 1980 statements at 20 per ms: under basic_statements_without_wait (2000)
  EXPECT_EQ(count(d.device(), RuleId::script_busy_loop), 0U);
  d.step(2);
  EXPECT_EQ(count(d.device(), RuleId::script_busy_loop), 1U);
  // a polling loop waits (GETOBJ) and saves once a second: a store in a loop
  ASSERT_EQ(
      d.device().upload_program(
          2, "DEF_TIM_VAR t\n:l\nSTART_TIM 1000\n:w\nIF t > 0 THEN GOTO w\nb = GETOBJ $6041.00\nSAVE b\nGOTO l\n"),
      basic::Programs::Upload::ok);
  ASSERT_EQ(d.device().basic()->start(2), basic::Programs::Start::ok);
  d.step(3500);
  EXPECT_EQ(count(d.device(), RuleId::script_busy_loop), 1U);
  EXPECT_GE(count(d.device(), RuleId::script_flash_write_in_loop), 2U);
}

}  // namespace
}  // namespace mcemu::device
