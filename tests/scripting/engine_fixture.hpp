// A drive with a script engine for engine tests: a real io_context, a drive bundle built by the one
// fixture (tests/support/device_fixture.hpp: dictionary, core, I/O functions, RefGo interpreter …)
// and Debian's /usr/bin/python3. The engine is wired as the server wires it: after the bundle's
// step, the event hand-off after every module call. Drive time advances only through
// advance(), which keeps lock-step with the script like `--clock manual` (scripting.md §8.2): a
// step waits until the script sleeps, pauses or ends (or 1 s of wall time has passed). Conditions
// are polled with a generous wall-clock bound; nothing sleeps for a fixed time.
#pragma once

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "iofunc/io_functions.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "scripting/engine.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::scripting::test {

struct EngineRig {
  explicit EngineRig(const std::string& model = "MC349", EngineSettings settings = {},
                     const core::PlantConfig& plant = {})
      : fixture(model, options(plant)),
        preset(fixture.preset()),
        od(fixture.od()),
        core(fixture.core()),
        io_fn(fixture.io()),
        in(fixture.refgo()) {
    fixture.step();
    EngineCallbacks cb;
    cb.console = [this](std::string m) { console.push_back(std::move(m)); };
    cb.record_changed = [this](const nlohmann::json& r) { records.push_back(r); };
    cb.after_call = [this] { fixture.device().handle_events(); };
    cb.calls = [this](std::uint64_t n) { calls.push_back(n); };
    cb.run_changed = [this](bool running) { runs.push_back(running); };
    engine = std::make_unique<ScriptEngine>(io, od, core, in, std::move(cb), std::move(settings));
  }
  ~EngineRig() { engine.reset(); }

  // The loop for a moment. An io_context without pending work stops; the server's never runs out
  // of work (its acceptors), the rig may between two runs, so it restarts it.
  void run_loop() {
    if (io.stopped()) io.restart();
    io.run_one_for(std::chrono::milliseconds(1));
  }
  void poll_loop() {
    if (io.stopped()) io.restart();
    io.poll();
  }
  // One drive step as the server runs it, then the engine's step.
  void step() {
    fixture.step();
    engine->on_step();
    ++steps;
  }
  // Runs the loop until the engine is ready for the next step (bounded by its own 1 s rule).
  void settle() {
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    auto ready = std::make_shared<bool>(engine->ready_for_step());
    if (!*ready) engine->when_ready_for_step([ready] { *ready = true; });
    while (!*ready && std::chrono::steady_clock::now() < limit) run_loop();
    EXPECT_TRUE(*ready) << "the engine never became ready for the next step";
    poll_loop();
  }
  // n lock-step steps of 1 ms.
  void advance(std::uint64_t n) {
    for (std::uint64_t i = 0; i < n; ++i) {
      settle();
      step();
    }
    settle();
  }
  // Advances in lock-step until pred() holds (true) or max_ms passed (false).
  bool advance_until(const std::function<bool()>& pred, std::uint64_t max_ms) {
    for (std::uint64_t i = 0; i < max_ms; ++i) {
      settle();
      if (pred()) return true;
      step();
    }
    settle();
    return pred();
  }
  // Runs the loop (no drive time) until pred() holds or `wall` passed.
  bool wait(const std::function<bool()>& pred, std::chrono::milliseconds wall = std::chrono::seconds(20)) {
    const auto limit = std::chrono::steady_clock::now() + wall;
    while (!pred()) {
      if (std::chrono::steady_clock::now() > limit) return false;
      run_loop();
    }
    return true;
  }

  // Uploads and starts `source`; returns once it runs (the compile step is 100 ms later).
  void start(const std::string& source) {
    ASSERT_EQ(engine->upload(source), UploadResult::ok);
    console.clear();
    engine->start();
  }
  // Start, then advance until the script is OFF again (or max_ms).
  bool run(const std::string& source, std::uint64_t max_ms = 10000) {
    start(source);
    return advance_until([&] { return engine->state() == RunState::off; }, max_ms);
  }

  std::string text() const {
    std::string all;
    for (const auto& m : console) all += m;
    return all;
  }
  std::int64_t get(std::uint16_t index, std::uint8_t sub = 0) const { return od.number(index, sub); }
  std::int64_t read(std::uint16_t index, std::uint8_t sub = 0) const {
    auto v = od.read_number(index, sub);
    return v.ok() ? *v : -1;
  }
  od::AbortCode write(std::uint16_t index, std::uint8_t sub, std::int64_t v, od::Origin o = od::Origin::sdo) {
    return od.write(index, sub, od::Value{v}, o);
  }

  static mcemu::testing::DeviceOptions options(const core::PlantConfig& plant) {
    mcemu::testing::DeviceOptions o;
    o.plant = plant;
    o.keep_events = false;
    return o;
  }

  boost::asio::io_context io;
  mcemu::testing::DeviceFixture fixture;
  const model::ModelPreset& preset;
  od::ObjectDictionary& od;
  core::DriveCore& core;
  iofunc::IoFunctions& io_fn;
  refgo::Interpreter& in;
  std::vector<std::string> console;
  std::vector<nlohmann::json> records;
  std::vector<std::uint64_t> calls;  // EngineCallbacks::calls: calls since the last wait, per report
  std::vector<bool> runs;            // EngineCallbacks::run_changed, in order
  std::unique_ptr<ScriptEngine> engine;
  std::uint64_t steps = 0;
};

// VmRSS of this process in KiB.
std::int64_t rss_kib();

}  // namespace mcemu::scripting::test
