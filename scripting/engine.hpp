// MovingCap CODE (scripting.md): the script engine of one drive, owned by the composition root.
// It holds the loaded script, runs it in a separate python3 process per run (engine_process.hpp),
// executes the script's module calls on the loop (core/calls.hpp), produces the `code:` console
// lines and the script's output (udp-debug.md §4.2–§4.6), and implements 3500h.01–.06 and 1F51h.01.
//
// Contract:
// - Everything on the event-loop thread, which must also be the thread that constructs it (the
//   engine forks from it). The dictionary, core and interpreter must outlive the engine; the
//   constructor registers read/write hooks on 3500h.01/.02/.03/.05/.06 and 1F51h.01 and the
//   destructor removes them and kills any engine process (blocking, briefly).
// - Time is drive time (DriveCore::time_ms()): on_step() must run after every drive step.
// - A script can never block or crash the loop: its requests are read like any non-blocking peer,
//   at most 64 per loop turn; a stop is SIGKILL to its process group and takes effect at once.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/liveness.hpp"
#include "drive/drive_core.hpp"
#include "drive/od/dictionary.hpp"
#include "scripting/core/calls.hpp"
#include "scripting/core/console_output.hpp"
#include "scripting/core/ipc.hpp"
#include "scripting/core/lifecycle.hpp"
#include "scripting/core/script_source.hpp"

namespace mcemu::refgo {
class Interpreter;
}
namespace mcemu::trace {
class Ring;
}

namespace mcemu::scripting {

class EngineProcess;
class PythonProbe;
class SandboxProbe;

// Runtime settings (web.md §8.9) and the host side of the engine. strict and memory_mib apply from
// the next start; trace_calls at once.
struct EngineSettings {
  std::string python = "/usr/bin/python3";  // Debian's interpreter, not one on PATH
  bool strict = true;                       // scriptStrict (scripting.md §9)
  unsigned memory_mib = 256;                // scriptMemoryMiB; below 32 → 32
  bool trace_calls = false;                 // traceScriptCalls
  std::string bind_address = "127.0.0.1";   // the drive's --bind: mcnet sockets bind here
  bool interpolate_us = true;               // ticks_us between steps from the host clock (real clock only)
  // The OS sandbox (docs/security.md): every run goes through bwrap with the seccomp filters. If
  // the start-up probe finds that it cannot be set up, scripts do not start — unless unsafe_scripts
  // (--unsafe-scripts) allows running them without it. `sandbox = false` is for tests only.
  bool sandbox = true;
  bool unsafe_scripts = false;
  std::string bwrap = "/usr/bin/bwrap";  // "scripting.bwrap" of --config
};

struct EngineCallbacks {
  // One console message with its own line end: UDP console (udp-debug.md §3) and web mirror.
  std::function<void(std::string message)> console;
  // The program group's script record changed (upload, delete, factory reset, power cycle): what
  // Store Permanently will keep — persistence::Service::set_script().
  std::function<void(const nlohmann::json& record)> record_changed;
  // After every module call of the script (e.g. drain the core's events: EMCY, faults).
  std::function<void()> after_call;
  // After every module call and every sleep: the calls the script made since it last waited (a
  // sleep, or a call answered later, such as a blocking read) — the master lint's script.busy_loop.
  std::function<void(std::uint64_t calls_since_wait)> calls;
  // After a batch of the engine's messages or its exit was handled outside a drive step: the
  // drive, the next deadline or the lock-step readiness may have changed (a call, a sleep begun
  // or cancelled, the run ended) — the clock re-plans (ClockDriver::wake).
  std::function<void()> changed;
  // Before the first message of such a batch reads or changes the drive: the drive's own time
  // brought up to the clock's (ClockDriver::settle — a fleet leaves its quiet drives behind).
  std::function<void()> settle;
  // A run began (true: its process was started) or ended (false: it is gone, for whatever reason):
  // only a drive whose engine has a run can hold the manual clock (ready_for_step), so the server
  // counts them instead of asking every drive of a fleet after every step.
  std::function<void(bool running)> run_changed;
};

enum class UploadResult : std::uint8_t { ok, empty, too_large };

class ScriptEngine {
 public:
  ScriptEngine(boost::asio::io_context& io, od::ObjectDictionary& od, core::DriveCore& core, refgo::Interpreter& refgo,
               EngineCallbacks callbacks, EngineSettings settings = {}, trace::Ring* trace = nullptr);
  ~ScriptEngine();
  ScriptEngine(const ScriptEngine&) = delete;
  ScriptEngine& operator=(const ScriptEngine&) = delete;

  // ---- availability (scripting.md §10.1.8): probed once — in the background 1 s after
  // construction (a short-lived process never pays for it), or at once when asked earlier; see
  // PythonProbe
  bool available() const;
  const std::string& engine_version() const;  // "CPython 3.11.2" or the reason
  // Whether runs are sandboxed, and in words: what the sandbox is ("bubblewrap 0.8.0, seccomp, …")
  // when they are, else the one sentence why not (also when unavailable for another reason: "").
  bool sandboxed() const;
  const std::string& sandbox_text() const;
  bool unsafe() const;  // runs without the sandbox because --unsafe-scripts allowed it

  // ---- the program (web.md §6.1, §8.7)
  // 1 … 65 536 bytes: stops a running script, the two upload lines, replaces the source (RAM).
  UploadResult upload(std::string bytes);
  void delete_script();  // 1F51h.01 := 3: stop, placeholder in RAM
  const ScriptSource& source() const { return source_; }
  const std::string& id() const { return source_.id(); }
  std::string_view source_visible() const { return source_.visible(); }
  bool has_private() const { return source_.has_private(); }
  std::uint32_t crc32() const { return source_.crc32(); }
  std::uint32_t length() const { return source_.length(); }
  nlohmann::json record() const { return source_.record(); }

  // ---- life cycle (scripting.md §3; codeAct of web.md §6.2)
  void start();                 // codeAct=3, RUN/Restart, POST …/start: start, or restart from the top
  void stop();                  // codeAct=4
  void pause();                 // codeAct=1
  void resume();                // codeAct=2
  void code_act(int n);         // 1–6 as web.md §6.2 (5/6: autostart on/off in RAM); others ignored
  void set_autostart(bool on);  // 3500h.04 := on (RAM; origin web)
  void kill();                  // fault injection script.kill: the engine dies (engine-failure line)
  void trigger(Trigger t);      // any trigger of core/lifecycle.hpp (tests, server)
  RunState state() const { return state_; }
  // Engine processes not yet reaped (a stopped one stays until its exit is seen).
  std::size_t live_processes() const { return processes_.size(); }
  std::uint32_t line() const;  // 3500h.03 (unsaturated)

  // ---- power (persistence.md §7)
  // Power loss / NMT reset node: the engine is terminated and the stored script (record as on
  // disk; null = placeholder) becomes the RAM script.
  void power_cycle(const nlohmann::json& stored_record);
  // After the start-up messages (or after an NMT reset node): start if 3500h.04 — which the RAM
  // image rebuild just set to the stored flag — is 1.
  void autostart_after_power_up();
  // persistence::ServiceHooks::reset_script: a factory reset was applied.
  void factory_reset();

  // ---- time
  void on_step();  // after every drive step: drive time to the engine, sleeps, compile, output
  std::optional<std::uint64_t> next_deadline_ms() const;

  // ---- --clock manual lock-step (scripting.md §8.2): before each step the clock driver asks
  // ready_for_step(); if false it calls when_ready_for_step() and steps when called back (once the
  // script sleeps, pauses or ends, or after 1 s of wall time).
  bool ready_for_step() const;
  void when_ready_for_step(std::function<void()> ready);

  // ---- settings
  const EngineSettings& settings() const { return settings_; }
  void set_strict(bool on) { settings_.strict = on; }
  void set_memory_mib(unsigned mib) { settings_.memory_mib = mib; }
  void set_trace_calls(bool on) { settings_.trace_calls = on; }
  void set_interpolate_us(bool on) { settings_.interpolate_us = on; }

 private:
  struct Run;
  void apply(Trigger t, std::optional<ScriptSource> uploaded = {}, const nlohmann::json* stored = nullptr);
  void launch();
  void terminate(bool forward_output);
  void freeze();
  void thaw();
  void freeze_poll(const std::shared_ptr<Run>& run, std::uint64_t gen, std::uint32_t seq, int polls);
  void pump(const std::shared_ptr<Run>& run);
  void handle(const std::shared_ptr<Run>& run, ipc::Message& m, bool calls);
  void handle_call(const std::shared_ptr<Run>& run, const std::string& body);
  void handle_net(const std::shared_ptr<Run>& run, const std::string& body);
  void answer_net(const std::shared_ptr<Run>& run, const ipc::NetRequest& request, const std::string& peer);
  void reply(const std::shared_ptr<Run>& run, const Values& values);
  void on_exit(const std::shared_ptr<Run>& run, int status);
  void protocol_error(const std::shared_ptr<Run>& run, const std::string& what);
  void emit(std::string message);
  void output(std::string_view bytes);
  void settled();
  void arm_line_timer(const std::shared_ptr<Run>& run);
  void arm_settle_timer();
  void install_hooks();
  std::uint64_t now_ms() const;
  void trace_event(std::string text);

  boost::asio::io_context& io_;
  od::ObjectDictionary& od_;
  core::DriveCore& core_;
  refgo::Interpreter& refgo_;
  EngineCallbacks callbacks_;
  EngineSettings settings_;
  trace::Ring* trace_;
  void start_probe() const;
  void resolve_probe() const;
  // From its start until its answer is read; shared by every engine of the process with the same
  // settings (a fleet of 1000 drives starts one probe, not 1000).
  mutable std::shared_ptr<PythonProbe> probe_;
  mutable std::shared_ptr<SandboxProbe> sandbox_probe_;
  mutable bool probed_ = false;
  mutable bool available_ = false;
  mutable bool sandboxed_ = false;
  mutable bool unsafe_ = false;
  mutable std::string version_;
  mutable std::string sandbox_text_;
  ScriptSource source_;
  RunState state_ = RunState::off;
  std::shared_ptr<Run> run_;
  std::vector<std::shared_ptr<EngineProcess>> processes_;  // not yet reaped
  std::uint32_t line_ = 0;
  OutputCooker cooker_;
  CallContext calls_;
  std::uint64_t generation_ = 0;
  // lock-step
  bool settled_ = true;
  bool abandoned_ = false;
  RunState traced_state_ = RunState::off;  // the last state change put on the trace
  std::vector<std::function<void()>> waiters_;
  boost::asio::steady_timer settle_timer_;
  base::LivenessToken alive_;  // timers, process callbacks and late replies check it
  boost::asio::steady_timer probe_timer_;
  std::unique_ptr<boost::asio::ip::tcp::resolver> resolver_;  // mcnet peers given by name
};

}  // namespace mcemu::scripting
