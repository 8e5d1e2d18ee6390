// The script engine with Debian's /usr/bin/python3 (scripting.md §3, §4, §10; udp-debug.md §4.2–
// §4.6): life cycle and its console lines, tracebacks, objects 3500h/1F51h, drive time.
#include "scripting/engine.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "tests/scripting/engine_fixture.hpp"

namespace mcemu::scripting::test {

std::int64_t rss_kib() {
  std::ifstream f("/proc/self/status");
  std::string key;
  while (f >> key) {
    if (key == "VmRSS:") {
      std::int64_t v = 0;
      f >> v;
      return v;
    }
    std::string rest;
    std::getline(f, rest);
  }
  return 0;
}

namespace {

const std::string k_id = "maxTRACK N23 demo rev8";

TEST(Engine, IsAvailableWithDebiansPython) {
  EngineRig r;
  EXPECT_TRUE(r.engine->available()) << r.engine->engine_version();
  EXPECT_EQ(r.engine->engine_version().rfind("CPython 3.", 0), 0U);
}

TEST(Engine, StartPrintsTheDluLinesInOrder) {  // udp-debug.md §7.2
  EngineRig r;
  r.start("#id " + k_id + "\nprint(\"Hello World from MovingCap!\")\n");
  EXPECT_EQ(r.engine->state(), RunState::run);
  EXPECT_EQ(r.read(0x3500, 2), 1);
  ASSERT_EQ(r.console, (std::vector<std::string>{"code: starting, script id: " + k_id + "\n\r"}));
  r.advance(99);
  EXPECT_EQ(r.console.size(), 1U);  // compile exactly 100 ms after the start request
  ASSERT_TRUE(r.advance_until([&] { return r.engine->state() == RunState::off; }, 5000));
  EXPECT_EQ(r.console, (std::vector<std::string>{
                           "code: starting, script id: " + k_id + "\n\r", "code: compile, script id: " + k_id + "\n\r",
                           "code: execute, script id: " + k_id + "\n\r", "Hello World from MovingCap!\r\n"}));
  EXPECT_EQ(r.read(0x3500, 2), 0);
  EXPECT_EQ(r.runs, (std::vector<bool>{true, false})) << "the run's begin and end, once each";
}

TEST(Engine, CompileErrorOfTheDluVector) {  // udp-debug.md §7.3
  EngineRig r;
  std::string src = "#id " + k_id + "\n";
  for (int i = 2; i <= 21; ++i) src += "x = 1\n";
  src += " x = 2\n";
  ASSERT_TRUE(r.run(src));
  EXPECT_EQ(r.text(), "code: starting, script id: " + k_id + "\n\rcode: compile, script id: " + k_id +
                          "\n\rTraceback (most recent call last):\r\n  File \"<stdin>\", line 22\r\n"
                          "IndentationError: unexpected indent\r\n");
  EXPECT_EQ(r.read(0x3500, 2), 0);
  EXPECT_EQ(r.read(0x3500, 3), 22);
}

TEST(Engine, RuntimeErrorTracebackAndLine) {  // udp-debug.md §7.4
  EngineRig r;
  ASSERT_TRUE(r.run("def f():\n    return 1 // 0\nf()\n"));
  EXPECT_NE(r.text().find("code: execute, script id: (empty)\n\rTraceback (most recent call last):\r\n"
                          "  File \"<stdin>\", line 3, in <module>\r\n  File \"<stdin>\", line 2, in f\r\n"
                          "ZeroDivisionError: division by zero\r\n"),
            std::string::npos)
      << r.text();
  EXPECT_EQ(r.read(0x3500, 3), 2);
}

// The master lint's script.busy_loop (docs/lint.md §8.1): every call reports the calls since the
// script last waited; a sleep reports 0 and starts the count again.
TEST(Engine, CallsSinceTheLastWait) {
  EngineRig r;
  ASSERT_TRUE(
      r.run("import mcdrive, time\nfor i in range(50):\n    mcdrive.ReadStatusword()\n"
            "time.sleep_ms(10)\nfor i in range(3):\n    mcdrive.ReadStatusword()\n"));
  ASSERT_GE(r.calls.size(), 54U);
  const std::vector<std::uint64_t> tail(r.calls.end() - 4, r.calls.end());
  EXPECT_EQ(tail, (std::vector<std::uint64_t>{0, 1, 2, 3}));
  EXPECT_EQ(*std::max_element(r.calls.begin(), r.calls.end()), 50U);
}

TEST(Engine, SleepFollowsDriveTimeExactly) {  // scripting.md §13.7: one print per 1000 ms
  EngineRig r;
  r.start(
      "import time\nt0 = time.ticks_ms()\nwhile True:\n    print(time.ticks_diff(time.ticks_ms(), t0))\n"
      "    time.sleep_ms(1000)\n");
  r.advance(100);  // compile
  r.advance(3500);
  std::vector<std::string> prints(r.console.begin() + 3, r.console.end());
  EXPECT_EQ(prints, (std::vector<std::string>{"0\r\n", "1000\r\n", "2000\r\n", "3000\r\n"}));
  r.engine->stop();
  EXPECT_EQ(r.engine->state(), RunState::off);
}

}  // namespace
}  // namespace mcemu::scripting::test

namespace mcemu::scripting::test {
namespace {

// ---- life cycle (scripting.md §3.2) and objects (§2.4)

TEST(EngineLifecycle, UploadLinesRecordAndObjects) {
  EngineRig r;
  EXPECT_EQ(r.engine->upload(""), UploadResult::empty);
  EXPECT_EQ(r.engine->upload(std::string(65537, '#')), UploadResult::too_large);
  EXPECT_TRUE(r.console.empty());
  ASSERT_EQ(r.engine->upload("#id up 1\nprint(1)\n#private\nx = 2\n"), UploadResult::ok);
  EXPECT_EQ(r.console,
            (std::vector<std::string>{"code: starting upload...\r\n", "code: upload complete, script id: up 1\r\n"}));
  ASSERT_EQ(r.records.size(), 1U);
  EXPECT_EQ(r.records[0]["id"], "up 1");
  auto id = r.od.read(0x3500, 1);
  ASSERT_TRUE(id);
  EXPECT_EQ(std::get<std::string>(*id), "up 1");
  EXPECT_EQ(r.read(0x3500, 5), 33);
  EXPECT_EQ(r.engine->source_visible(), "#id up 1\nprint(1)\n");
  EXPECT_TRUE(r.engine->has_private());
  EXPECT_EQ(r.write(0x1F51, 1, 3), od::AbortCode::none);  // delete: the placeholder
  EXPECT_EQ(r.read(0x3500, 5), 13);
  EXPECT_EQ(r.read(0x3500, 6), 0x23883CEF);
  EXPECT_TRUE(r.records.back().is_null());
}

TEST(EngineLifecycle, RunControlObject) {
  EngineRig r;
  ASSERT_EQ(r.engine->upload("import time\nwhile True:\n    time.sleep_ms(10)\n"), UploadResult::ok);
  EXPECT_EQ(r.write(0x3500, 2, 1), od::AbortCode::none);
  EXPECT_EQ(r.read(0x3500, 2), 1);
  r.advance(200);
  EXPECT_EQ(r.write(0x3500, 2, 2), od::AbortCode::none);  // pause
  EXPECT_EQ(r.read(0x3500, 2), 2);
  EXPECT_EQ(r.read(0x1F51, 1), 2);
  EXPECT_EQ(r.write(0x3500, 2, 1), od::AbortCode::none);  // resume
  EXPECT_EQ(r.engine->state(), RunState::run);
  EXPECT_EQ(r.write(0x3500, 2, 3), od::AbortCode::invalid_value);
  EXPECT_EQ(r.write(0x3500, 2, 0), od::AbortCode::none);  // stop
  EXPECT_EQ(r.engine->state(), RunState::off);
  EXPECT_EQ(r.write(0x3500, 2, 2), od::AbortCode::none);  // pause while OFF: nothing
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineLifecycle, ProgramControlStartRestartStop) {
  EngineRig r;
  ASSERT_EQ(r.engine->upload("#id pc\nimport time\nprint('up')\nwhile True:\n    time.sleep_ms(10)\n"),
            UploadResult::ok);
  r.console.clear();
  EXPECT_EQ(r.write(0x1F51, 1, 1), od::AbortCode::none);
  r.advance(200);
  EXPECT_EQ(r.write(0x1F51, 1, 1), od::AbortCode::none);  // start while RUN: nothing
  EXPECT_EQ(r.write(0x1F51, 1, 2), od::AbortCode::none);  // restart
  r.advance(200);
  EXPECT_EQ(r.engine->state(), RunState::run);
  std::size_t starts = 0, ups = 0;
  for (const auto& m : r.console) {
    starts += m.rfind("code: starting", 0) == 0;
    ups += m == "up\r\n";
  }
  EXPECT_EQ(starts, 2U);
  EXPECT_EQ(ups, 2U);
  EXPECT_EQ(r.write(0x1F51, 1, 0), od::AbortCode::none);
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineLifecycle, PauseFreezesAndAPassedSleepReturnsAtOnceAfterResume) {
  EngineRig r;
  r.start("import time\nwhile True:\n    time.sleep_ms(1000)\n    print(time.ticks_ms())\n");
  r.advance(300);
  r.engine->pause();
  EXPECT_EQ(r.engine->state(), RunState::brk);
  const std::size_t before = r.console.size();
  r.advance(5000);  // paused: drive time goes on, the script does nothing
  EXPECT_EQ(r.console.size(), before);
  r.engine->resume();
  ASSERT_TRUE(r.wait([&] { return r.console.size() > before; }));
  EXPECT_EQ(r.console.back(), std::to_string(r.core.time_ms()) + "\r\n");
  r.engine->stop();
}

TEST(EngineLifecycle, ScriptStopsItselfThroughTheObject) {
  EngineRig r;
  ASSERT_TRUE(r.run("import mcdrive as mc\nprint('a')\nmc.WriteObject(0x3500, 2, 0)\nprint('never')\n"));
  EXPECT_NE(r.text().find("a\r\n"), std::string::npos);
  EXPECT_EQ(r.text().find("never"), std::string::npos);
}

TEST(EngineLifecycle, ScriptRestartsItselfFromTheTop) {
  EngineRig r;
  r.start("import refgo\nimport time\nprint('top')\ntime.sleep_ms(50)\nrefgo.cmd('OW1F51,1,2')\nprint('never')\n");
  r.advance(400);
  EXPECT_EQ(r.text().find("never"), std::string::npos);
  std::size_t tops = 0;
  for (const auto& m : r.console) tops += m == "top\r\n";
  EXPECT_GE(tops, 2U);
  r.engine->stop();
}

TEST(EngineLifecycle, UploadWhileRunningStops) {
  EngineRig r;
  r.start("while True:\n    pass\n");
  r.advance(150);
  EXPECT_EQ(r.engine->upload("print(2)\n"), UploadResult::ok);
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineLifecycle, PowerCycleLoadsTheStoredScriptAndAutostarts) {
  EngineRig r;
  const nlohmann::json stored = ScriptSource::from_bytes("#id stored\nprint('boot')\n").record();
  r.start("while True:\n    pass\n");
  r.advance(150);
  r.engine->power_cycle(stored);
  EXPECT_EQ(r.engine->state(), RunState::off);
  EXPECT_EQ(r.engine->id(), "stored");
  r.console.clear();
  r.engine->autostart_after_power_up();  // 3500h.04 = 0: nothing
  EXPECT_TRUE(r.console.empty());
  ASSERT_EQ(r.write(0x3500, 4, 1), od::AbortCode::none);
  r.engine->autostart_after_power_up();
  EXPECT_EQ(r.engine->state(), RunState::run);
  ASSERT_TRUE(r.advance_until([&] { return r.engine->state() == RunState::off; }, 3000));
  EXPECT_EQ(r.console.back(), "boot\r\n");
  r.engine->power_cycle(nullptr);  // nothing stored: the placeholder
  EXPECT_EQ(r.engine->id(), "(empty)");
}

TEST(EngineLifecycle, PowerCycleDropsAHeldPartialLine) {  // udp-debug.md §4.4 across a power loss
  EngineRig r;
  r.start("import sys\nprint('x', end='')\nwhile True:\n    sys.wait(1000)\n");
  ASSERT_TRUE(r.advance_until([&] { return r.text().find("code: execute") != std::string::npos; }, 3000));
  r.advance(10);  // the 'x' is held (50 ms rule)
  r.console.clear();
  r.engine->power_cycle(nullptr);
  EXPECT_FALSE(r.engine->next_deadline_ms()) << "nothing held any more";
  r.advance(100);
  EXPECT_EQ(r.text(), "") << "the partial line is lost with the power";
}

TEST(EngineLifecycle, FactoryResetLoadsThePlaceholder) {
  EngineRig r;
  r.start("while True:\n    pass\n");
  r.advance(150);
  r.engine->factory_reset();
  EXPECT_EQ(r.engine->state(), RunState::off);
  EXPECT_EQ(r.read(0x3500, 5), 13);
}

TEST(EngineLifecycle, PlaceholderRunsAndEnds) {
  EngineRig r;
  r.engine->start();
  ASSERT_TRUE(r.advance_until([&] { return r.engine->state() == RunState::off; }, 3000));
  EXPECT_EQ(r.console.size(), 3U);  // starting, compile, execute
}

TEST(EngineLifecycle, CodeActs) {
  EngineRig r;
  ASSERT_EQ(r.engine->upload("import time\nwhile True:\n    time.sleep_ms(5)\n"), UploadResult::ok);
  r.engine->code_act(3);
  EXPECT_EQ(r.engine->state(), RunState::run);
  r.advance(150);
  r.engine->code_act(1);
  EXPECT_EQ(r.engine->state(), RunState::brk);
  r.engine->code_act(2);
  EXPECT_EQ(r.engine->state(), RunState::run);
  r.engine->code_act(5);
  EXPECT_EQ(r.get(0x3500, 4), 1);
  r.engine->code_act(6);
  EXPECT_EQ(r.get(0x3500, 4), 0);
  r.engine->code_act(99);
  r.engine->code_act(4);
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineLifecycle, UnavailableEngine) {
  EngineSettings s;
  s.python = "/nonexistent/python3";
  EngineRig r("MC349", s);
  EXPECT_FALSE(r.engine->available());
  r.engine->start();
  EXPECT_EQ(r.console, (std::vector<std::string>{"code: starting, script id: (empty)\n\r",
                                                 "code: engine unavailable, script id: (empty)\n\r"}));
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineLifecycle, KilledEngineReportsTheSignal) {  // script.kill, udp-debug.md §4.6
  EngineRig r;
  r.start("while True:\n    pass\n");
  r.advance(150);
  r.engine->kill();
  ASSERT_TRUE(r.wait([&] { return r.engine->state() == RunState::off; }));
  EXPECT_EQ(r.console.back(), "code: engine failure (signal 9), script id: (empty)\n\r");
}

TEST(EngineLifecycle, CurrentLineIsSampled) {
  EngineRig r;
  r.start("x = 0\nwhile True:\n    x += 1\n");
  r.advance(150);
  ASSERT_TRUE(r.wait([&] { return r.read(0x3500, 3) == 3 || r.read(0x3500, 3) == 2; }));
  r.engine->stop();
}

}  // namespace
}  // namespace mcemu::scripting::test
