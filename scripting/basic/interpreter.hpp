// The MC BASIC executor (faulhaber.md §9.3–§9.9): runs one loaded program in drive time.
//
// Contract:
// - Pure, single-threaded, deterministic: no thread, no clock. The owner calls step(now_ms) once per
//   1 ms drive step, after the drive core's step; a step first advances the timers by the drive
//   time elapsed since the previous step, then runs up to Settings::statements_per_ms statements
//   (label lines, comments, ELSE, ENDIF and the jump from a branch's end to its ENDIF are free; a
//   one-line IF with its statement is one). The bound holds for every program.
// - Every GETOBJ/SETOBJ is one ObjectDictionary call with origin `script`; the variables a … z are
//   the entries 0x3005.01 … .1A, read and written through the dictionary at every use, so a value
//   a master wrote between two statements is what the next statement sees. Events read 0x2324.01
//   before every statement while a handler is registered.
// - Run-time errors stop the program in state `error` with the line and, for OD failures, the abort
//   code. Events (events.hpp) go to the sink synchronously.
// - Idle detection (quiet_steps/skip, the sim::Part contract): a step is *pure* when it wrote no
//   object value that changed, executed no SETOBJ, SAVE, LOAD, FOR or NEXT, read no entry the
//   Settings::time_dependent predicate names, and no timer counted. When the dictionary did not
//   change since the end of the last step and the interpreter's control state (line, GOSUB stack,
//   event and timer state) at the end of a pure step equals its state at the start of one of the
//   last 64 consecutive pure steps, the program provably repeats that cycle until an object value
//   changes: quiet_steps() answers "never" and skip(n) puts the control state where n steps would
//   have left it. A program polling an input that does not change thus costs nothing.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "scripting/basic/events.hpp"
#include "scripting/basic/program.hpp"
#include "scripting/basic/storage.hpp"

namespace mcemu::basic {

// Same value as sim::k_forever: no step needed.
inline constexpr std::uint64_t k_never = std::numeric_limits<std::uint64_t>::max();

// The largest statements_per_ms a configuration may ask for (faulhaber.basic_statements_per_ms): a
// drive step runs its statements whole, so this bounds one step's CPU (docs/faulhaber.md).
inline constexpr std::uint32_t k_max_statements_per_ms = 250;

struct Settings {
  std::uint32_t statements_per_ms = 20;  // faulhaber.basic_statements_per_ms; 0 counts as 1
  bool idle_detection = true;
  // Entries whose value can change while the drive is otherwise quiet (read hooks computed from
  // drive time alone); a GETOBJ of one keeps the program busy. Empty: none.
  std::function<bool(std::uint16_t index, std::uint8_t sub)> time_dependent;
};

enum class RunState : std::uint8_t { idle, running, stopped, finished, error };
std::string_view to_string(RunState s);

struct RunError {
  std::uint32_t line = 0;
  std::string message{};
  od::AbortCode code = od::AbortCode::none;
};

class Interpreter {
 public:
  Interpreter(od::ObjectDictionary& od, VariableStorage& storage, Settings settings = {}, EventSink sink = {});

  // Runs `program` from its first line: no GOSUB, no handler, timers undefined; the variables keep
  // their values (§9.9). A running program is stopped first. `program` must stay alive and
  // unchanged until this run ends (stop(), another start(), the end or an error).
  void start(const Program& program, int slot = 0);
  // A running program stops (event `stopped` with `why`); otherwise nothing happens.
  void stop(std::string_view why = "stop request");

  void step(std::uint64_t now_ms);
  std::uint64_t quiet_steps() const;  // k_never: step() would change nothing (see above)
  void skip(std::uint64_t n);         // n ≤ quiet_steps() steps at once

  RunState state() const { return state_; }
  bool running() const { return state_ == RunState::running; }
  int slot() const { return slot_; }
  const RunError& error() const { return error_; }
  // The line of the statement about to run (running), of the error (error).
  std::optional<std::uint32_t> line() const;
  std::uint64_t statements() const { return statements_; }  // run since construction
  std::uint64_t save_count() const { return save_count_; }  // SAVE statements since construction
  // Statements since the program last waited (the master lint's script.busy_loop): a GETOBJ, a read
  // of its timer variable, an event check while a handler is registered, or a skipped polling
  // cycle (idle detection) is a wait; so is the start of a run.
  std::uint64_t statements_since_wait() const { return statements_ - waited_at_; }
  std::size_t gosub_depth() const { return m_.depth; }
  bool idle() const { return cycle_len_ > 0; }  // a repeating pure cycle is known

  const Settings& settings() const { return settings_; }
  void set_statements_per_ms(std::uint32_t n);

 private:
  struct Frame {
    std::uint32_t return_pc = 0;
    bool event = false;
    bool operator==(const Frame&) const = default;
  };
  // Everything a step's behaviour depends on besides the dictionary and the loops (FOR/NEXT make a
  // step impure): the unit of idle detection.
  struct Machine {
    std::uint32_t pc = 0;
    std::uint8_t depth = 0;
    std::int8_t event_frame = -1;  // stack index of the running handler's frame
    std::array<Frame, k_max_gosub_depth> stack{};
    bool ev_enabled = false;
    bool ev_pending = false;  // an edge seen during the handler
    std::int8_t ev_var = -1;
    std::uint32_t ev_mask = 0;
    std::uint32_t ev_handler = 0;
    std::uint32_t ev_last = 0;  // 0x2324.01 & mask at the last check
    std::int8_t tim_var = -1;
    bool tim_running = false;
    std::int8_t cyc_var = -1;
    bool cyc_running = false;
    bool operator==(const Machine&) const = default;
  };
  struct LoopState {
    bool active = false;
    std::int32_t to = 0;
    std::int32_t step = 1;
  };
  static constexpr std::size_t k_history = 64;

  void run(std::uint32_t budget);
  void execute(const Instr& in);
  bool check_event();
  void advance_timers(std::uint64_t elapsed);
  bool eval(const ExprRange& r, std::int32_t& out, std::uint32_t line);
  bool read_object(std::uint16_t index, std::uint8_t sub, std::int32_t& out, std::uint32_t line);
  bool read_var(std::uint8_t var, std::int32_t& out, std::uint32_t line);
  bool write_var(std::uint8_t var, std::int32_t value, std::uint32_t line);
  void setobj(const Instr& in, std::int32_t value);
  void save(const Instr& in);
  void fail(std::uint32_t line, std::string message, od::AbortCode code = od::AbortCode::none);
  void finish(RunState s, EventKind kind, std::string_view message);
  void emit(Event e);
  void forget_history();
  void remember(const Machine& at_start);

  od::ObjectDictionary& od_;
  VariableStorage& storage_;
  Settings settings_;
  EventSink sink_;
  const Program* prog_ = nullptr;
  RunState state_ = RunState::idle;
  int slot_ = 0;
  RunError error_;
  Machine m_;
  std::vector<LoopState> loops_;
  std::uint64_t now_ms_ = 0;
  bool have_time_ = false;
  std::uint64_t statements_ = 0;
  std::uint64_t save_count_ = 0;
  std::uint64_t waited_at_ = 0;  // statements_ at the last wait
  bool impure_ = false;
  // idle detection: step-start states of consecutive pure steps (a ring) and the cycle found in it
  std::array<Machine, k_history> history_{};
  std::size_t hist_head_ = 0;  // oldest
  std::size_t hist_count_ = 0;
  std::vector<Machine> cycle_;  // cycle_[0] = the state of the next step
  std::size_t cycle_len_ = 0;
  std::uint64_t last_end_generation_ = 0;
};

}  // namespace mcemu::basic
