// Idle costs nothing (issue 13, README "Time"): one whole drive as the server composes it — I/O
// functions and core, fault injections with durations, RefGo programs, the event hand-off (EMCY to
// the CANopen node, LED status), the CANopen bus with an SLCAN client — driven three ways:
//   1. a full step every 1 ms (the old clock),
//   2. sim::advance() with quiet stretches skipped,
//   3. the clock logic under a fake wall clock, woken only when it asks or when a client acts,
// gives exactly the same object values, core events, CAN frames (with their Z1 timestamps), LED
// states and RefGo replies. Scenario: boot, heartbeat on, NMT start, a TPDO event timer, an SDO
// timeout, an input timer that starts a move, enabled standing, a fault injection with a duration
// and its reset, a RefGo timed jog and Back & Forth, then a long idle stretch with heartbeats.
#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>

#include "sim/clock_logic.hpp"
#include "sim/drive_steps.hpp"
#include "tests/sim/trace_text.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::server {
namespace {

using Wall = sim::ClockLogic::Wall;

struct Drive {
  // the bundle as the server builds it (tests/support/device_fixture.hpp); core events and I/O
  // diagnostics reach the trace through the fixture's taps
  testing::DeviceFixture fx{"MC349", options()};
  od::ObjectDictionary& od = fx.od();
  core::DriveCore& core = fx.core();
  device::FaultInjections& faults = fx.device().faults();
  refgo::Interpreter& refgo = fx.refgo();
  led::Leds& leds = fx.device().leds();
  sim::DriveSteps& steps = fx.device().steps();
  std::unique_ptr<line::StreamSession> client;
  std::vector<std::string> trace;

  static testing::DeviceOptions options() {
    testing::DeviceOptions o;
    o.keep_events = false;
    return o;
  }
  Drive() {
    fx.on_event = [this](const core::Event& e) { trace.push_back(stamp() + sim::test::event_text(e)); };
    fx.on_log = [this](const std::string& text) { trace.push_back(stamp() + "io " + text); };
    client = fx.device().canopen()->make_session();
    fx.device().canopen()->power_on();
  }
  // App::on_core_events plus the LED status: the bundle's event hand-off
  void hand_off() { fx.device().handle_events(); }
  std::string stamp() const { return std::to_string(core.time_ms()) + " "; }
  void frames() {
    const std::string out = client->take_output();
    if (!out.empty()) trace.push_back(stamp() + "can " + out);
  }
  void checkpoint() {
    frames();
    const auto v = leds.green.view(core.time_ms());
    std::string led = stamp();
    led += "led ";
    led += std::to_string(v.on);
    led += ' ';
    led += v.schedule->text;
    led += ' ';
    led += std::to_string(v.cycle_start_ms);
    if (v.next) {
      led += " next ";
      led += v.next->text;
    }
    led += " yellow ";
    led += std::to_string(leds.yellow.on(core.time_ms()));
    trace.push_back(led);
    for (auto& line : sim::test::od_dump(od)) trace.push_back(stamp() + line);
  }
  // a client action: what the server does between steps, then the drive is touched
  void client_action(const std::function<void(Drive&)>& act) {
    act(*this);
    hand_off();
    frames();
    steps.touch();
  }
  void can(const std::string& line) { client->receive(line); }
  void refgo_line(const std::string& line) {
    const auto reply = refgo.execute(line);
    trace.push_back(stamp() + "refgo " + line + " -> " + (reply ? *reply : "(later)"));
  }
  void W(std::uint16_t i, std::uint8_t s, std::int64_t v) {
    trace.push_back(stamp() + "write " + std::to_string(i) + "." + std::to_string(s) + " " +
                    std::to_string(static_cast<std::uint32_t>(od.write(i, s, od::Value{v}, od::Origin::sdo))));
  }
};

struct Action {
  std::uint64_t at;
  std::function<void(Drive&)> act;
};

const std::vector<Action>& scenario() {
  static const std::vector<Action> a = {
      {5, [](Drive& d) { d.can("Z1\r"); }},
      {100, [](Drive& d) { d.can("t63282B171000FA000000\r"); }},   // 1017h := 250 ms heartbeat
      {1000, [](Drive& d) { d.can("t00020132\r"); }},              // NMT start node 50
      {1200, [](Drive& d) { d.can("t63282B001805F4010000\r"); }},  // 1800h.05 := 500 ms event timer
      {2000, [](Drive& d) { d.can("t63284008100000000000\r"); }},  // upload 1008h: segmented, then silence
      {4000,
       [](Drive& d) {  // iofunc.md IN-4: rising edge, 1 s delay, move to 6300
         d.W(0x6067, 0, 10);
         d.W(0x3511, 1, 1024);
         d.W(0x3511, 5, 1000);
         d.W(0x3511, 8, 6300);
         d.W(0x3511, 6, 500);
         d.W(0x3511, 7, 400);
         d.W(0x3511, 9, 200);
         d.core.set_external_input_level(1, true);
       }},
      {8000,
       [](Drive& d) {
         const auto r = d.faults.create(R"({"kind": "drive.inject", "cause": "under_voltage", "durationMs": 3000})");
         d.trace.push_back(d.stamp() + "fault " + (std::holds_alternative<nlohmann::json>(r) ? "201" : "refused"));
       }},
      {12000, [](Drive& d) { d.W(0x6040, 0, 0x80); }},
      {14000,
       [](Drive& d) {
         d.refgo_line("PWC");
         d.refgo_line("JP300");
       }},
      {15000,
       [](Drive& d) {
         d.refgo_line("RW2000");
         d.refgo_line("WT200");
         d.refgo_line("RR");
       }},
      {20000,
       [](Drive& d) {
         d.refgo_line("SM");
         d.refgo_line("PQ");
       }},
      {21000, [](Drive& d) { d.leds.yellow.activity(d.core.time_ms()); }},
      {30000, [](Drive& d) { d.can("t00020132\r"); }},
  };
  return a;
}

constexpr std::uint64_t k_end = 60000;

enum class Path { stepping, catch_up, clock };

struct Result {
  std::vector<std::string> trace;
  std::uint64_t full = 0;
  std::uint64_t wake_ups = 0;
};

Result run(Path path) {
  Drive d;
  Result r;
  sim::ClockLogic clock(d.steps, sim::ClockMode{});
  clock.start(Wall(0));
  const auto wall = [](std::uint64_t ms) { return Wall(static_cast<std::int64_t>(ms) * 1000000); };
  const auto go_to = [&](std::uint64_t t) {
    switch (path) {
      case Path::stepping:
        while (d.core.time_ms() < t) {
          d.steps.step();
          ++r.full;
        }
        return;
      case Path::catch_up: r.full += d.steps.advance_to(t).full; return;
      case Path::clock: {
        // the driver's loop: wake up when the plan says, never before; then a client at t
        for (;;) {
          const auto next = clock.plan();
          if (next.kind == sim::ClockLogic::Next::Kind::sleep_until && next.at <= wall(t)) {
            clock.on_wake(next.at);
            ++r.wake_ups;
          } else {
            break;
          }
        }
        clock.sync(wall(t));
        r.full = clock.full_steps();
        return;
      }
    }
  };
  std::size_t next = 0;
  for (std::uint64_t t = 1000; t <= k_end; t += 1000) {
    while (next < scenario().size() && scenario()[next].at < t) {
      go_to(scenario()[next].at);
      d.checkpoint();
      d.client_action(scenario()[next].act);
      ++next;
    }
    go_to(t);
    d.checkpoint();
  }
  r.trace = std::move(d.trace);
  return r;
}

TEST(IdleEquivalence, WholeDriveCatchUpEqualsOneMillisecondSteps) {
  const Result a = run(Path::stepping);
  const Result b = run(Path::catch_up);
  const Result c = run(Path::clock);
  ASSERT_EQ(a.trace.size(), b.trace.size());
  for (std::size_t i = 0; i < a.trace.size(); ++i) ASSERT_EQ(a.trace[i], b.trace[i]) << "line " << i;
  ASSERT_EQ(a.trace.size(), c.trace.size());
  for (std::size_t i = 0; i < a.trace.size(); ++i) ASSERT_EQ(a.trace[i], c.trace[i]) << "line " << i;
  std::printf("60 s scenario: full steps 1 ms path %llu, catch-up %llu, clock %llu (%llu timer wake-ups)\n",
              static_cast<unsigned long long>(a.full), static_cast<unsigned long long>(b.full),
              static_cast<unsigned long long>(c.full), static_cast<unsigned long long>(c.wake_ups));
  EXPECT_EQ(a.full, k_end);
  if (std::getenv("IDLE_TRACE")) {  // the scenario's events and frames, for a reader
    for (const auto& l : a.trace) {
      if (l.find('=') == std::string::npos) std::printf("%s\n", l.c_str());
    }
  }
  EXPECT_LT(b.full * 2, a.full);
  // the scenario really did what it says
  const auto seen = [&](const std::string& what) {
    return std::any_of(a.trace.begin(), a.trace.end(),
                       [&](const auto& l) { return l.find(what) != std::string::npos; });
  };
  EXPECT_TRUE(seen("t732105")) << "heartbeat in OPERATIONAL";
  EXPECT_TRUE(seen("can t1B2")) << "TPDO1";
  EXPECT_TRUE(seen("t5B2880")) << "SDO abort (timeout)";
  EXPECT_TRUE(seen(" reached 1")) << "input timer move";
  EXPECT_TRUE(seen(" fault 12833")) << "under-voltage injection";
  EXPECT_TRUE(seen(" reset")) << "fault reset";
  EXPECT_TRUE(seen("refgo RR -> ")) << "Back & Forth";
  EXPECT_TRUE(seen("next MC+IP192+168+2+150+ERR3221:")) << "LED announced the fault text";
}

}  // namespace
}  // namespace mcemu::server
