// DriveUnit, the script side (scripting.md): one ScriptEngine per drive and its wiring — console
// lines to the UDP debug service (udp-debug.md §4.2–§4.6, byte for byte as the engine makes them),
// the script record to persistence, the event hand-off after every module call, a step part whose
// quiet steps come from the engine's deadlines, the lock-step with --clock manual, power cycle and
// NMT reset node with autostart, the runtime settings, and the JSON API's view (ScriptControl).
// The logic is the engine's (scripting/) and the router's (web/api/handlers_script.cpp).
#include "drive/od/objects.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "scripting/engine.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_unit.hpp"
#include "web/api/services.hpp"

namespace mcemu::server {

namespace {

using scripting::RunState;
using scripting::ScriptEngine;

// The optional "scripting" section of --config: { "python": "/usr/bin/python3", "bwrap":
// "/usr/bin/bwrap" } — the interpreter the engine runs (scripting.md §10.2: Debian's python3, not
// one found on PATH) and the bubblewrap of its sandbox (docs/security.md).
void scripting_section(const nlohmann::json& config, scripting::EngineSettings& es) {
  const auto it = config.find("scripting");
  if (it == config.end()) return;
  for (const auto& [key, value] : it->items()) {
    if (key != "python" && key != "bwrap") {
      throw UsageError("config: unknown key \"scripting." + key + "\" (known: python, bwrap)");
    }
    if (!value.is_string() || value.get<std::string>().empty()) {
      throw UsageError("config: \"scripting." + key + "\" must be the path of " +
                       (key == "python" ? "a python3 executable" : "the bwrap executable"));
    }
    (key == "python" ? es.python : es.bwrap) = value.get<std::string>();
  }
}

}  // namespace

// The JSON API's and /program.html's view of the engine (web/api/services.hpp).
class DriveUnit::ScriptWeb final : public web::api::ScriptControl {
 public:
  explicit ScriptWeb(DriveUnit& unit) : unit_(unit) {}

  bool available() const override { return eng() != nullptr && eng()->available(); }
  std::string engine() const override {
    if (!eng()) return "script engine shut down";
    std::string v = eng()->engine_version();  // "CPython 3.11.2", or why it is unavailable
    if (!eng()->available()) return v;
    constexpr std::string_view prefix = "CPython ";
    if (v.rfind(prefix, 0) == 0) v.erase(0, prefix.size());
    return "python3 " + v;  // web.md §8.1
  }
  web::api::SandboxView sandbox() const override {
    const ScriptEngine* e = eng();
    if (!e || (e->sandbox_text().empty() && !e->sandboxed())) return {};  // no python3: nothing to say
    return web::api::SandboxView{true, e->sandboxed(), e->unsafe(), e->sandbox_text()};
  }
  web::api::ScriptView view() const override {
    web::api::ScriptView v;
    v.id = "(empty)";
    v.state = "OFF";
    const ScriptEngine* e = eng();
    if (!e) return v;
    v.id = e->id();
    v.state = std::string(scripting::to_string(e->state()));
    v.autostart = unit_.device_->od().number(od::k_script, od::k_script_autostart) != 0;
    v.length = e->length();
    v.crc32 = e->crc32();
    v.line = static_cast<int>(std::min<std::uint32_t>(e->line(), 255));  // as 3500h.03
    v.source = std::string(e->source_visible());
    v.has_private = e->has_private();
    return v;
  }
  std::optional<std::string> upload(std::string source) override {
    if (!eng()) return "script engine shut down";
    switch (eng()->upload(std::move(source))) {
      case scripting::UploadResult::ok: return std::nullopt;
      case scripting::UploadResult::empty: return "empty script";
      case scripting::UploadResult::too_large: return "script larger than 65536 bytes";
    }
    return "upload refused";
  }
  void start() override { act(&ScriptEngine::start); }
  void stop() override { act(&ScriptEngine::stop); }
  void pause() override { act(&ScriptEngine::pause); }
  void resume() override { act(&ScriptEngine::resume); }
  void kill() override { act(&ScriptEngine::kill); }
  void code_act(int n) override {
    if (eng()) eng()->code_act(n);
  }
  web::api::PythonStatus status() const override {
    const ScriptEngine* e = eng();
    if (!e) return {};
    return web::api::PythonStatus{std::string(scripting::to_string(e->state())),
                                  static_cast<int>(std::min<std::uint32_t>(e->line(), 255))};
  }
  int refgo_attach_mode() const override { return static_cast<int>(unit_.device_->refgo()->attachment().mode()); }

 private:
  ScriptEngine* eng() const { return unit_.engine_.get(); }
  void act(void (ScriptEngine::*f)()) {
    if (eng()) (eng()->*f)();
  }

  DriveUnit& unit_;
};

web::api::ScriptControl& DriveUnit::script_control() {
  if (!script_web_) script_web_ = std::make_unique<ScriptWeb>(*this);
  return *script_web_;
}

// After build_web (the trace ring and the runtime settings' start values exist); the stored
// script becomes the RAM script as at every power-up.
void DriveUnit::build_script() {
  scripting::EngineCallbacks cb;
  cb.console = [this](std::string message) { udp_debug_->emit(std::move(message)); };
  cb.record_changed = [this](const nlohmann::json& record) { device_->persistence().set_script(record); };
  cb.after_call = [this] { device_->handle_events(); };  // EMCY, faults, UDP notes of the call's effects
  if (device_->lint().active()) {
    cb.calls = [this](std::uint64_t n) { device_->lint().script_loop(lint::ScriptKind::code, n); };
  }
  cb.changed = [this] { wake(); };
  cb.settle = [this] { settle(); };
  cb.run_changed = [this](bool running) {
    if (running == script_run_) return;
    script_run_ = running;
    if (script_runs_) running ? ++*script_runs_ : --*script_runs_;
  };
  const auto& rs = device_->settings();
  scripting::EngineSettings es;
  scripting_section(settings_.config, es);
  es.unsafe_scripts = settings_.unsafe_scripts;
  es.strict = rs.script_strict;
  es.memory_mib = static_cast<unsigned>(rs.script_memory_mib);
  es.trace_calls = rs.trace_script_calls;
  es.bind_address = settings_.bind;
  engine_ = std::make_unique<ScriptEngine>(io_, device_->od(), device_->core(), *device_->refgo(), std::move(cb),
                                           std::move(es), &device_->trace());
  script_power_down();
  device_->add_part(script_part());
  device_->faults().set_script_kill([this] { return engine_ && engine_->state() != RunState::off; },
                                    [this] {
                                      if (engine_) engine_->kill();
                                    });
}

// The engine after the drive in every step (scripting/README.md). Quiet steps come from its
// deadlines (compile, a sleep, held output), so an idle drive — also one whose script sleeps —
// lets the clock sleep. Under the real and scaled clocks a script that is running code reads drive
// time from the shared page without asking (ticks_ms, a polling loop), so the drive is stepped
// every 1 ms while it does; a skip publishes the drive time reached.
std::unique_ptr<sim::Part> DriveUnit::script_part() {
  const auto& core = device_->core();
  return std::make_unique<sim::FunctionPart>(
      [this] {
        if (engine_) engine_->on_step();
      },
      [this, &core]() -> std::uint64_t {
        if (!engine_) return sim::k_forever;
        if (!clock_manual_ && engine_->state() == RunState::run && !engine_->ready_for_step()) return 0;
        const auto due = engine_->next_deadline_ms();
        return due ? sim::steps_before(*due, core.time_ms()) : sim::k_forever;
      },
      [this](std::uint64_t) {
        if (engine_) engine_->on_step();
      });
}

void DriveUnit::attach_clock(ClockDriver& clock, std::size_t* script_runs) {
  clock_ = &clock;
  script_runs_ = script_runs;
  if (script_runs_ && script_run_) ++*script_runs_;  // an autostarted script
  clock_manual_ = clock.mode().kind == sim::ClockMode::Kind::manual;
  // ticks_us between two steps from the host clock only where drive time is wall time
  if (engine_) engine_->set_interpolate_us(clock.mode().kind == sim::ClockMode::Kind::real);
}

bool DriveUnit::script_holds_clock() {
  if (!engine_ || engine_->ready_for_step()) return false;
  if (!hold_waiting_) {
    hold_waiting_ = true;
    engine_->when_ready_for_step([this, alive = alive_.watch()] {
      if (!alive) return;
      hold_waiting_ = false;
      if (clock_) clock_->resume();
    });
  }
  return true;
}

// Power loss and NMT reset node (persistence.md §7): the engine is terminated and the script as
// stored on disk (the placeholder if none) becomes the RAM script.
void DriveUnit::script_power_down() {
  if (!engine_) return;
  const auto& file = device_->persistence().on_file();
  engine_->power_cycle(file ? file->script : nlohmann::json());
}

// After the start-up block (or at once after an NMT reset node): 3500h.04, just rebuilt from the
// file, decides (scripting.md §3.2).
void DriveUnit::script_power_up() {
  if (engine_) engine_->autostart_after_power_up();
}

void DriveUnit::apply_script_settings(const device::RuntimeSettings& s) {
  if (!engine_) return;
  engine_->set_strict(s.script_strict);
  engine_->set_memory_mib(static_cast<unsigned>(s.script_memory_mib));
  engine_->set_trace_calls(s.trace_script_calls);
}

}  // namespace mcemu::server
