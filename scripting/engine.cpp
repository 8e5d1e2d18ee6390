#include "scripting/engine.hpp"

#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <map>

#include "drive/od/objects.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "scripting/engine_process.hpp"
#include "scripting/net_open.hpp"
#include "scripting/sandbox.hpp"
#include "trace/trace.hpp"

namespace mcemu::scripting {

namespace asio = boost::asio;
using ipc::Kind;
using ipc::Value;

namespace {

constexpr std::uint64_t k_compile_delay_ms = 100;  // udp-debug.md §4.3
constexpr int k_requests_per_turn = 64;            // scripting.md §10.1.4
constexpr auto k_line_sample = std::chrono::milliseconds(100);
constexpr auto k_freeze_poll = std::chrono::milliseconds(1);
constexpr int k_freeze_polls = 10;  // wait at most 10 ms for the line sample before SIGSTOP
constexpr auto k_settle_budget = std::chrono::seconds(1);
constexpr auto k_compile_budget = std::chrono::seconds(10);
constexpr auto k_probe_delay = std::chrono::seconds(1);
constexpr auto k_probe_collect = std::chrono::seconds(2);

std::uint64_t mono_ns() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

// The availability found by the first engine of the process for these settings: the probe runs
// once, not once per drive of a fleet (every engine lives on the loop thread).
struct ProbeOutcome {
  bool available = false;
  bool sandboxed = false;
  bool unsafe = false;
  std::string version;       // "CPython 3.11.2", or why the engine is unavailable
  std::string sandbox_text;  // what the sandbox is, or why there is none
};
std::map<std::string, ProbeOutcome>& probe_cache() {
  static std::map<std::string, ProbeOutcome> cache;
  return cache;
}
// The probes started and not yet read, by the same key: every engine whose timer fires before the
// first answer is read shares them instead of starting python3 and bwrap once more.
struct ProbesInFlight {
  std::shared_ptr<PythonProbe> python;
  std::shared_ptr<SandboxProbe> sandbox;
};
std::map<std::string, ProbesInFlight>& probes_in_flight() {
  static std::map<std::string, ProbesInFlight> flights;
  return flights;
}
std::string probe_key(const EngineSettings& s) {
  return s.python + '\n' + s.bwrap + '\n' + (s.sandbox ? "s" : "-") + (s.unsafe_scripts ? "u" : "-");
}

std::string describe(const ipc::Value& v) {
  switch (v.tag) {
    case Value::Tag::none: return "None";
    case Value::Tag::integer: return std::to_string(v.i);
    case Value::Tag::bytes:
    case Value::Tag::text: return "'" + v.s + "'";
  }
  return "?";
}

}  // namespace

enum class Phase : std::uint8_t { waiting_compile, compiling, running };

struct ScriptEngine::Run {
  explicit Run(asio::io_context& io) : line_timer(io), freeze_timer(io) {}
  std::uint64_t gen = 0;
  std::shared_ptr<EngineProcess> proc;
  Phase phase = Phase::waiting_compile;
  std::string id;      // the script id at the start request
  std::string source;  // the bytes at the start request
  std::uint64_t compile_due_ms = 0;
  std::optional<std::uint64_t> sleep_due_ms;
  std::uint64_t calls_since_wait = 0;
  bool frozen = false;   // paused: requests are held
  bool hello = false;    // the runner is up: its SIGUSR1 handler is installed
  bool stopped = false;  // SIGSTOP sent (paused)
  std::uint64_t freeze_gen = 0;
  asio::steady_timer line_timer;
  asio::steady_timer freeze_timer;
};

ScriptEngine::ScriptEngine(asio::io_context& io, od::ObjectDictionary& od, core::DriveCore& core,
                           refgo::Interpreter& refgo, EngineCallbacks callbacks, EngineSettings settings,
                           trace::Ring* trace)
    : io_(io),
      od_(od),
      core_(core),
      refgo_(refgo),
      callbacks_(std::move(callbacks)),
      settings_(std::move(settings)),
      trace_(trace),
      calls_{{core, od, od::Origin::script}, refgo, {}},
      settle_timer_(io),
      probe_timer_(io) {
  calls_.refused = [this](std::string text) { trace_event(std::move(text)); };
  install_hooks();
  // The probe costs python3's start-up (tens of ms of CPU): not during the emulator's own, and not
  // at all for a process that lives less than a second; its answer is collected a little later.
  probe_timer_.expires_after(k_probe_delay);
  const auto alive = alive_.watch();
  probe_timer_.async_wait([this, alive](const boost::system::error_code& ec) {
    if (ec || !alive) return;
    start_probe();
    probe_timer_.expires_after(k_probe_collect);
    probe_timer_.async_wait([this, alive](const boost::system::error_code& ec2) {
      if (!ec2 && alive) resolve_probe();
    });
  });
}

void ScriptEngine::start_probe() const {
  if (probed_ || probe_ || probe_cache().count(probe_key(settings_))) return;
  auto& flight = probes_in_flight()[probe_key(settings_)];
  if (!flight.python) flight.python = std::make_shared<PythonProbe>(settings_.python);
  if (settings_.sandbox && !flight.sandbox)
    flight.sandbox = std::make_shared<SandboxProbe>(settings_.bwrap, settings_.python);
  probe_ = flight.python;
  sandbox_probe_ = flight.sandbox;
}

void ScriptEngine::resolve_probe() const {
  if (probed_) return;
  const std::string key = probe_key(settings_);
  auto cached = probe_cache().find(key);
  if (cached == probe_cache().end()) {
    start_probe();
    ProbeOutcome o;
    std::string why;
    if (auto v = probe_->result(why)) {
      o.version = "CPython " + *v;
      if (!settings_.sandbox) {
        o.available = true;
        spdlog::info("script engine: {} ({}), no sandbox", o.version, settings_.python);
      } else if (const auto& verdict = sandbox_probe_->result(); verdict.ok) {
        o.available = o.sandboxed = true;
        o.sandbox_text = bwrap_version(settings_.bwrap) +
                         ": no network, read-only /usr, private /tmp, own PID and IPC namespaces, seccomp, user " +
                         (geteuid() == 0 ? "nobody (65534)" : "of mcemu");
        spdlog::info("script engine: {} ({}), sandbox {}", o.version, settings_.python, o.sandbox_text);
      } else if (settings_.unsafe_scripts) {
        o.available = o.unsafe = true;
        o.sandbox_text = sandbox::unsafe_sentence(verdict.reason);
        spdlog::warn("script engine: {} ({}) — {}", o.version, settings_.python, o.sandbox_text);
      } else {
        o.sandbox_text = sandbox::unavailable_sentence(verdict.reason);
        o.version = o.sandbox_text;
        spdlog::warn("script engine unavailable: {}", o.sandbox_text);
      }
    } else {
      o.version = why;
      spdlog::warn("script engine unavailable: {}; scripts cannot run", why);
    }
    cached = probe_cache().emplace(key, std::move(o)).first;
    probes_in_flight().erase(key);  // the engines that shared them drop their share below
  }
  probed_ = true;
  const ProbeOutcome& o = cached->second;
  available_ = o.available;
  sandboxed_ = o.sandboxed;
  unsafe_ = o.unsafe;
  version_ = o.version;
  sandbox_text_ = o.sandbox_text;
  probe_.reset();
  sandbox_probe_.reset();
}

bool ScriptEngine::available() const {
  resolve_probe();
  return available_;
}

const std::string& ScriptEngine::engine_version() const {
  resolve_probe();
  return version_;
}

bool ScriptEngine::sandboxed() const {
  resolve_probe();
  return sandboxed_;
}

const std::string& ScriptEngine::sandbox_text() const {
  resolve_probe();
  return sandbox_text_;
}

bool ScriptEngine::unsafe() const {
  resolve_probe();
  return unsafe_;
}

ScriptEngine::~ScriptEngine() {
  alive_.end();
  for (const auto& [index, sub] : {std::pair<std::uint16_t, std::uint8_t>{od::k_script, od::k_script_id},
                                   {od::k_script, od::k_script_state},
                                   {od::k_script, od::k_script_line},
                                   {od::k_script, od::k_script_length},
                                   {od::k_script, od::k_script_crc32},
                                   {od::k_program_control, 1}}) {
    if (od_.find(index, sub)) od_.on_read(index, sub, {});
  }
  if (od_.find(od::k_script, od::k_script_state)) od_.on_write(od::k_script, od::k_script_state, {});
  if (od_.find(od::k_program_control, 1)) od_.on_write(od::k_program_control, 1, {});
  if (run_) refgo_.attachment().close();
  for (auto& p : processes_) p->kill_and_reap();
}

// ---- objects (scripting.md §2.4)

void ScriptEngine::install_hooks() {
  const auto read = [this](std::uint16_t index, std::uint8_t sub, std::function<od::Value()> fn) {
    if (od_.find(index, sub))
      od_.on_read(index, sub, [fn](const od::EntryInfo&) -> od::Result<od::Value> { return fn(); });
  };
  read(od::k_script, od::k_script_id, [this] { return od::Value{source_.id()}; });
  read(od::k_script, od::k_script_state, [this] { return od::Value{run_control_value(state_)}; });
  read(od::k_script, od::k_script_line,
       [this] { return od::Value{std::int64_t{std::min<std::uint32_t>(line(), 255)}}; });
  read(od::k_script, od::k_script_length, [this] { return od::Value{std::int64_t{source_.length()}}; });
  read(od::k_script, od::k_script_crc32, [this] { return od::Value{std::int64_t{source_.crc32()}}; });
  read(od::k_program_control, 1, [this] { return od::Value{run_control_value(state_)}; });
  if (od_.find(od::k_script, od::k_script_state)) {
    od_.on_write(od::k_script, od::k_script_state, [this](od::WriteRequest& r) {
      if (auto t = run_control_trigger(std::get<std::int64_t>(r.value), state_)) trigger(*t);
      return od::AbortCode::none;
    });
  }
  if (od_.find(od::k_program_control, 1)) {
    od_.on_write(od::k_program_control, 1, [this](od::WriteRequest& r) {
      if (auto t = program_control_trigger(std::get<std::int64_t>(r.value))) trigger(*t);
      return od::AbortCode::none;
    });
  }
}

std::uint32_t ScriptEngine::line() const {
  if (run_ && run_->proc->page().line_seq() != 0) return run_->proc->page().line();
  return line_;
}

// ---- program and life cycle

UploadResult ScriptEngine::upload(std::string bytes) {
  if (bytes.empty()) return UploadResult::empty;
  if (bytes.size() > k_max_script_bytes) return UploadResult::too_large;
  apply(Trigger::upload, ScriptSource::from_bytes(std::move(bytes)));
  return UploadResult::ok;
}

void ScriptEngine::delete_script() { trigger(Trigger::delete_script); }
void ScriptEngine::start() { trigger(Trigger::restart); }
void ScriptEngine::stop() { trigger(Trigger::stop); }
void ScriptEngine::pause() { trigger(Trigger::pause); }
void ScriptEngine::resume() { trigger(Trigger::resume); }
void ScriptEngine::factory_reset() { trigger(Trigger::factory_reset); }

void ScriptEngine::code_act(int n) {
  if (n == 5 || n == 6) {
    set_autostart(n == 5);
    return;
  }
  if (auto t = code_act_trigger(n)) trigger(*t);
}

void ScriptEngine::set_autostart(bool on) {
  if (od_.find(od::k_script, od::k_script_autostart))
    od_.write(od::k_script, od::k_script_autostart, od::Value{std::int64_t{on ? 1 : 0}}, od::Origin::web);
}

void ScriptEngine::trigger(Trigger t) { apply(t); }

void ScriptEngine::kill() {
  if (run_) run_->proc->kill_group();
}

void ScriptEngine::power_cycle(const nlohmann::json& stored_record) {
  apply(Trigger::power_cycle, std::nullopt, &stored_record);
  // Power loss: a partial line still held is lost with the rest of the unsent output (and drive
  // time restarts at 0, so its 50 ms deadline would mean nothing).
  cooker_ = OutputCooker{};
}

void ScriptEngine::autostart_after_power_up() {
  if (state_ == RunState::off && od_.find(od::k_script, od::k_script_autostart) &&
      od_.number(od::k_script, od::k_script_autostart) == 1)
    trigger(Trigger::start);
}

void ScriptEngine::apply(Trigger t, std::optional<ScriptSource> uploaded, const nlohmann::json* stored) {
  const Decision d = decide(state_, t);
  if (d.terminate) terminate(true);
  state_ = d.next;
  switch (d.source) {
    case SourceChange::none: break;
    case SourceChange::uploaded:
      emit("code: starting upload...\r\n");
      emit("code: upload complete, script id: " + uploaded->id() + "\r\n");
      source_ = std::move(*uploaded);
      break;
    case SourceChange::placeholder: source_ = ScriptSource::placeholder(); break;
    case SourceChange::stored: source_ = ScriptSource::from_record(stored ? *stored : nlohmann::json()); break;
  }
  if (d.source != SourceChange::none) {
    line_ = 0;
    if (callbacks_.record_changed) callbacks_.record_changed(source_.record());
  }
  if (d.launch) launch();
  if (d.freeze) freeze();
  if (d.thaw) thaw();
  settled();
}

void ScriptEngine::launch() {
  const std::string id = source_.id();
  emit(starting_line(id));
  if (!available()) {
    if (!sandbox_text_.empty()) emit(engine_note_line(sandbox_text_));  // why: no sandbox
    emit(unavailable_line(id));
    state_ = RunState::off;
    return;
  }
  if (unsafe_) {
    spdlog::warn("script engine: starting \"{}\" WITHOUT the sandbox (--unsafe-scripts)", id);
    emit(engine_note_line(sandbox_text_));
  }
  std::string error;
  auto proc = EngineProcess::spawn(io_, {settings_.python, settings_.memory_mib, sandboxed_, settings_.bwrap}, error);
  if (!proc) {
    spdlog::error("script engine: cannot start {}: {}", settings_.python, error);
    emit(unavailable_line(id));
    state_ = RunState::off;
    return;
  }
  processes_.push_back(proc);
  auto run = std::make_shared<Run>(io_);
  run->gen = ++generation_;
  run->proc = proc;
  run->id = id;
  run->source = source_.bytes();
  run->compile_due_ms = now_ms() + k_compile_delay_ms;
  run_ = run;
  if (callbacks_.run_changed) callbacks_.run_changed(true);
  line_ = 0;
  proc->page().publish_time(now_ms(), mono_ns(), settings_.interpolate_us);
  const auto alive = alive_.watch();
  proc->on_exit([this, alive, run](int status) {
    if (alive) on_exit(run, status);
  });
  pump(run);
  arm_line_timer(run);
}

// §3.3: the engine is killed at once; the output it wrote before is forwarded, its unanswered
// requests are discarded (their replies check the run), the attachment is detached; its mcnet
// sockets close with the process.
void ScriptEngine::terminate(bool forward_output) {
  auto run = std::move(run_);
  run_.reset();
  if (!run) return;
  if (callbacks_.run_changed) callbacks_.run_changed(false);
  if (run->proc->page().line_seq() != 0) line_ = run->proc->page().line();
  run->line_timer.cancel();
  run->freeze_timer.cancel();
  run->proc->kill_group();
  if (forward_output) {
    run->proc->read_available();
    bool error = false;
    while (auto m = run->proc->next(error)) {
      if (m->kind == Kind::output) output(m->body);
    }
  }
  run->proc->close_channel();
  refgo_.attachment().close();
}

void ScriptEngine::freeze() {
  auto run = run_;
  if (!run) return;
  run->frozen = true;  // its requests are held from now on
  run->stopped = false;
  const std::uint64_t gen = ++run->freeze_gen;
  if (!run->hello) {  // still booting: nothing to sample, and SIGUSR1 would kill it
    run->proc->stop_group();
    run->stopped = true;
    return;
  }
  const std::uint32_t seq = run->proc->page().line_seq();
  run->proc->sample_line();
  freeze_poll(run, gen, seq, 0);
}

// SIGSTOP once the line sample is in, or after 10 ms (scripting.md §10.2).
void ScriptEngine::freeze_poll(const std::shared_ptr<Run>& run, std::uint64_t gen, std::uint32_t seq, int polls) {
  if (run != run_ || run->freeze_gen != gen || !run->frozen) return;
  if (run->proc->page().line_seq() == seq && polls < k_freeze_polls) {
    run->freeze_timer.expires_after(k_freeze_poll);
    const auto alive = alive_.watch();
    run->freeze_timer.async_wait([this, alive, run, gen, seq, polls](const boost::system::error_code& ec) {
      if (!ec && alive) freeze_poll(run, gen, seq, polls + 1);
    });
    return;
  }
  run->proc->stop_group();
  run->stopped = true;
  settled();
}

void ScriptEngine::thaw() {
  auto run = run_;
  if (!run) return;
  run->frozen = false;
  run->stopped = false;
  ++run->freeze_gen;
  run->freeze_timer.cancel();
  run->proc->continue_group();
  const auto alive = alive_.watch();
  asio::post(io_, [this, alive, run] {
    if (alive) pump(run);
  });
}

// ---- the channel

void ScriptEngine::pump(const std::shared_ptr<Run>& run) {
  int handled = 0;
  const auto done = [&] {
    if (handled > 0 && callbacks_.changed) callbacks_.changed();
  };
  for (int i = 0; i < k_requests_per_turn; ++i) {
    if (run != run_ || run->frozen) return done();
    bool error = false;
    auto m = run->proc->next(error);
    if (error) {
      protocol_error(run, "bad frame");
      ++handled;
      return done();
    }
    if (!m) {
      const auto alive = alive_.watch();
      run->proc->read_more([this, alive, run] {
        if (alive) pump(run);
      });
      return done();
    }
    if (handled == 0 && callbacks_.settle) callbacks_.settle();
    handle(run, *m, true);
    ++handled;
  }
  // budget spent: other handlers first (network events, the clock)
  const auto alive = alive_.watch();
  asio::post(io_, [this, alive, run] {
    if (alive) pump(run);
  });
  done();
}

void ScriptEngine::handle(const std::shared_ptr<Run>& run, ipc::Message& m, bool calls) {
  switch (m.kind) {
    case Kind::hello:
      run->hello = true;
      spdlog::debug("script engine: runner up (Python {})", m.body);
      return;
    case Kind::output: output(m.body); return;
    case Kind::call:
      if (calls) handle_call(run, m.body);
      return;
    case Kind::net:
      if (calls) handle_net(run, m.body);
      return;
    case Kind::compiled: {
      const auto v = ipc::decode_values(m.body);
      if (!v || v->size() != 2) return protocol_error(run, "bad compile report");
      if ((*v)[0].i != 0) {
        run->phase = Phase::running;
        emit(execute_line(run->id));
        if (!waiters_.empty()) arm_settle_timer();  // from now on the script's own 1 s
        return;
      }
      terminate(true);
      line_ = static_cast<std::uint32_t>((*v)[1].i);
      state_ = RunState::off;
      settled();
      return;
    }
    case Kind::sleep: {
      const auto v = ipc::decode_values(m.body);
      if (!v || v->size() != 1 || (*v)[0].tag != Value::Tag::integer) return protocol_error(run, "bad sleep");
      const std::int64_t us = (*v)[0].i;
      const std::uint64_t ms = us <= 0 ? 1 : static_cast<std::uint64_t>((us + 999) / 1000);
      run->sleep_due_ms = now_ms() + ms;
      run->calls_since_wait = 0;
      if (callbacks_.calls) callbacks_.calls(0);
      settled();
      return;
    }
    case Kind::cancel:
      if (run->sleep_due_ms) {
        run->sleep_due_ms.reset();
        run->proc->send(ipc::encode(Kind::wake, ""));
      }
      return;
    case Kind::end: {
      const auto v = ipc::decode_values(m.body);
      if (!v || v->size() != 2) return protocol_error(run, "bad end report");
      const std::int64_t line = (*v)[1].i;
      const bool exception = (*v)[0].i == static_cast<std::int64_t>(ipc::EndHow::exception);
      terminate(true);
      if (exception) line_ = static_cast<std::uint32_t>(line);
      state_ = RunState::off;
      settled();
      return;
    }
    case Kind::fatal: spdlog::error("script engine: runner failure: {}", m.body); return;
    case Kind::log: spdlog::warn("script: {}", m.body); return;
    case Kind::start:
    case Kind::reply:
    case Kind::wake: protocol_error(run, "unexpected message"); return;
  }
}

void ScriptEngine::handle_call(const std::shared_ptr<Run>& run, const std::string& body) {
  auto call = ipc::decode_call(body);
  if (!call) return protocol_error(run, "bad call");
  std::string text;
  if (trace_ && settings_.trace_calls) {
    const FunctionRow* row = find_function(call->function);
    text = row ? std::string(row->module) + "." + std::string(row->name) + "(" : "?(";
    for (std::size_t k = 0; k < call->args.size(); ++k) {
      if (k > 0) text += ", ";
      text += describe(call->args[k]);
    }
    text += ")";
  }
  const auto alive = alive_.watch();
  Later later = [this, alive, run, text](Values v) {
    if (!alive || run != run_) return;  // the run is over: the reply is discarded
    if (!text.empty()) trace_event(text + " -> " + (v.empty() ? "None" : describe(v[0])));
    reply(run, v);
  };
  bool malformed = false;
  auto r = execute_call(calls_, *call, later, malformed);
  if (malformed) return protocol_error(run, "malformed call");
  if (callbacks_.after_call) callbacks_.after_call();
  run->calls_since_wait = r ? run->calls_since_wait + 1 : 0;  // an answer that comes later: the script waits
  if (callbacks_.calls) callbacks_.calls(run->calls_since_wait);
  if (!r) return;
  if (!text.empty()) trace_event(text + " -> " + (r->empty() ? "None" : describe((*r)[0])));
  if (run == run_) reply(run, *r);
}

// mcnet (scripting.md §7): the socket is made here, in mcemu's network namespace, and handed over.
// A peer given by name is resolved in the background first (the loop never blocks on DNS); the
// script waits for the reply as for any call.
void ScriptEngine::handle_net(const std::shared_ptr<Run>& run, const std::string& body) {
  auto request = ipc::decode_net(body);
  if (!request) return protocol_error(run, "bad net request");
  if (request->kind == ipc::NetRequest::Kind::server || request->host.empty() || numeric_host(request->host)) {
    return answer_net(run, *request, request->host);
  }
  if (!resolver_) resolver_ = std::make_unique<asio::ip::tcp::resolver>(io_);
  resolver_->async_resolve(request->host, "",
                           [this, alive = alive_.watch(), run, r = *request](
                               const boost::system::error_code& ec, asio::ip::tcp::resolver::results_type res) {
                             if (!alive || run != run_) return;
                             std::string peer;  // IPv4 first, as the drive's own stack
                             if (!ec) {
                               for (const auto& e : res) {
                                 if (peer.empty() || e.endpoint().address().is_v4())
                                   peer = e.endpoint().address().to_string();
                                 if (e.endpoint().address().is_v4()) break;
                               }
                             }
                             // unresolved: a client fails and retries; a UDP peer keeps its name (its sends fail)
                             answer_net(run, r, peer.empty() && r.kind == ipc::NetRequest::Kind::udp ? r.host : peer);
                           });
}

void ScriptEngine::answer_net(const std::shared_ptr<Run>& run, const ipc::NetRequest& request,
                              const std::string& peer) {
  const NetOpened opened = open_net(request, settings_.bind_address, peer);
  Values v{Value::integer(opened.error), Value::text(peer)};
  if (opened.fd >= 0) {
    const bool sent = run->proc->send_with_fd(ipc::encode(Kind::reply, ipc::encode_values(v)), opened.fd);
    ::close(opened.fd);  // the script holds its own copy: the socket dies with the script
    if (sent) return;
    v[0] = Value::integer(ENOBUFS);
  }
  reply(run, v);
}

void ScriptEngine::reply(const std::shared_ptr<Run>& run, const Values& values) {
  run->proc->send(ipc::encode(Kind::reply, ipc::encode_values(values)));
}

void ScriptEngine::protocol_error(const std::shared_ptr<Run>& run, const std::string& what) {
  if (run != run_) return;
  spdlog::error("script engine: protocol error ({}); engine killed", what);
  const std::string id = run->id;
  terminate(false);
  emit(failure_signal_line(SIGKILL, id));
  state_ = RunState::off;
  settled();
}

void ScriptEngine::on_exit(const std::shared_ptr<Run>& run, int status) {
  std::erase(processes_, run->proc);
  if (run != run_) return;  // ended by mcemu or after reporting its end
  // It died on its own: what it wrote before still counts, in order (a normal end may be there).
  run->proc->read_available();
  if (callbacks_.settle) callbacks_.settle();
  bool error = false;
  while (auto m = run->proc->next(error)) {
    handle(run, *m, false);
    if (run != run_) {
      if (callbacks_.changed) callbacks_.changed();
      return;
    }
  }
  const std::string id = run->id;
  terminate(false);
  if (WIFSIGNALED(status)) {
    emit(failure_signal_line(WTERMSIG(status), id));
  } else {
    emit(failure_exit_line(WIFEXITED(status) ? WEXITSTATUS(status) : status, id));
  }
  state_ = RunState::off;
  settled();
  if (callbacks_.changed) callbacks_.changed();
}

// ---- output

void ScriptEngine::emit(std::string message) {
  if (callbacks_.console) callbacks_.console(std::move(message));
}

void ScriptEngine::output(std::string_view bytes) {
  for (auto& m : cooker_.write(bytes, now_ms())) emit(std::move(m));
}

void ScriptEngine::trace_event(std::string text) {
  if (trace_) trace_->record(trace::Channel::script, trace::Dir::event, text);
}

// ---- time

std::uint64_t ScriptEngine::now_ms() const { return core_.time_ms(); }

void ScriptEngine::on_step() {
  const std::uint64_t now = now_ms();
  if (auto run = run_) {
    run->proc->page().publish_time(now, mono_ns(), settings_.interpolate_us);
    if (run->phase == Phase::waiting_compile && now >= run->compile_due_ms) {
      emit(compile_line(run->id));
      std::string platver;
      if (auto v = od_.read(od::k_software_version, 0); v && std::holds_alternative<std::string>(*v))
        platver = std::get<std::string>(*v);
      Values start{Value::integer(settings_.strict ? 1 : 0), Value::integer(settings_.interpolate_us ? 1 : 0),
                   Value::text(settings_.bind_address), Value::text(platver), Value::bytes(run->source)};
      for (auto& v : table_values()) start.push_back(std::move(v));
      run->proc->send(ipc::encode(Kind::start, ipc::encode_values(start)));
      run->phase = Phase::compiling;
    }
    if (run->sleep_due_ms && now >= *run->sleep_due_ms) {
      run->sleep_due_ms.reset();
      run->proc->send(ipc::encode(Kind::wake, ""));
    }
  }
  if (auto m = cooker_.on_step(now)) emit(std::move(*m));
}

std::optional<std::uint64_t> ScriptEngine::next_deadline_ms() const {
  std::optional<std::uint64_t> due = cooker_.deadline_ms();
  const auto earliest = [&](std::uint64_t t) { due = due ? std::min(*due, t) : t; };
  if (run_ && run_->phase == Phase::waiting_compile) earliest(run_->compile_due_ms);
  if (run_ && run_->sleep_due_ms) earliest(*run_->sleep_due_ms);
  return due;
}

void ScriptEngine::arm_line_timer(const std::shared_ptr<Run>& run) {
  run->line_timer.expires_after(k_line_sample);
  const auto alive = alive_.watch();
  run->line_timer.async_wait([this, alive, run](const boost::system::error_code& ec) {
    if (ec || !alive || run != run_) return;
    if (state_ == RunState::run && run->hello) run->proc->sample_line();
    arm_line_timer(run);
  });
}

// ---- manual-clock lock-step

bool ScriptEngine::ready_for_step() const {
  if (!run_ || abandoned_) return true;
  if (state_ == RunState::brk) return run_->stopped;  // paused = frozen, not about to be
  return run_->phase == Phase::waiting_compile || run_->sleep_due_ms.has_value();
}

void ScriptEngine::when_ready_for_step(std::function<void()> ready) {
  if (ready_for_step()) {
    ready();
    return;
  }
  const bool first = waiters_.empty();
  waiters_.push_back(std::move(ready));
  if (first) arm_settle_timer();
}

// Booting python3 and compiling are the engine's time, not the script's: a longer bound there.
void ScriptEngine::arm_settle_timer() {
  settle_timer_.expires_after(run_ && run_->phase == Phase::compiling ? k_compile_budget : k_settle_budget);
  const auto alive = alive_.watch();
  settle_timer_.async_wait([this, alive](const boost::system::error_code& ec) {
    if (ec || !alive) return;
    abandoned_ = true;  // polls without sleeping: not waited for again until it next settles
    auto w = std::move(waiters_);
    waiters_.clear();
    for (auto& f : w) f();
  });
}

void ScriptEngine::settled() {
  if (state_ != traced_state_) {  // every state change passes here (trace channel script, web.md §8.6)
    traced_state_ = state_;
    trace_event("state " + std::string(to_string(state_)) + ", script id: " + source_.id());
  }
  if (!run_ || (state_ == RunState::brk && run_->stopped) || run_->phase == Phase::waiting_compile ||
      run_->sleep_due_ms) {
    abandoned_ = false;
  }
  if (waiters_.empty() || !ready_for_step()) return;
  settle_timer_.cancel();
  auto w = std::move(waiters_);
  waiters_.clear();
  for (auto& f : w) f();
}

}  // namespace mcemu::scripting
