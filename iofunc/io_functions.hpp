// The MovingCap I/O functions (iofunc.md): input functions 1–11 on 3511h–351Ah, the simulation
// objects 3510h.01/.02, output functions 1–6 on 3611h–3614h and the composed outputs 60FEh.01.
//
// Contract:
// - Pure and single-threaded (event-loop thread); no clock: "now" is DriveCore::time_ms().
// - The constructor registers the write hooks of 3510h.01/.02, 3511h–351Ah.01, 60FEh.01 and
//   3611h–3614h.01, one OD change listener, and the core's inputs observer. The dictionary and the
//   core must outlive this object; not copyable or movable (hooks capture `this`).
// - step() is the 1 ms tick of the whole drive (iofunc.md §3): queued edges and 3510h.02
//   commands, due timers, DriveCore::step(), output functions. The server calls it instead of
//   DriveCore::step().
// - power_on() replaces DriveCore::power_on(): the core powers on and iofunc's volatile state
//   (queue, timers, jog owner, feedback candidates, output latch) starts empty; levels already
//   high give no edge. after_bulk_load() follows every other bulk load of the OD (factory reset)
//   together with DriveCore::reload_parameters().
// - All effects are ordinary OD writes with origin internal, through the drive-core helpers
//   (drive-core.md §12); no unit conversion happens here.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/helpers/helpers.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/settings_cache.hpp"
#include "iofunc/io_handles.hpp"
#include "iofunc/output_functions.hpp"

namespace mcemu::iofunc {

// Something worth a log line ("dropped with a warning", iofunc.md §4); drained by the shell.
struct Diagnostic {
  core::DiagnosticLevel level;
  std::string text;
};

class IoFunctions {
 public:
  IoFunctions(od::ObjectDictionary& od, core::DriveCore& core);
  IoFunctions(const IoFunctions&) = delete;
  IoFunctions& operator=(const IoFunctions&) = delete;

  // ---- lifecycle and time
  void power_on(const core::PowerOnState& state = {});  // core.power_on(), then volatile state cleared
  void after_bulk_load();                               // core.reload_parameters(), timers/jog/candidates cleared
  void step();                                          // one 1 ms tick, iofunc.md §3
  void step(std::uint64_t n);
  // Idle (drive-core.md §2): how many of the next step() calls would change nothing but what
  // skip() reproduces — the core's quiet steps, cut at the first armed input timer; 0 while edges
  // or 3510h.02 commands are queued. skip(n) with n ≤ quiet_steps() = n quiet steps at once.
  std::uint64_t quiet_steps() const;
  void skip(std::uint64_t n) { core_.skip(n); }

  // ---- queries, no side effects
  bool teach_active() const;                                     // §4.10, on the levels applied so far
  std::optional<int> jog_owner() const { return jog_owner_; }    // input 1…10 owning a jog (§4.12)
  std::optional<std::uint64_t> timer_deadline(int input) const;  // armed delay of input 1…10 (ms)
  std::uint16_t feedback_candidates() const;                     // bit n−1 = IN n (§5.5)

  std::vector<Diagnostic> drain_diagnostics();

 private:
  enum class EventKind : std::uint8_t { rising, falling, command };
  struct Event {
    EventKind kind;
    int input;     // 1 … 10 (YY for a command)
    int function;  // ZZ for a command
  };
  struct Timer {
    std::uint64_t deadline;
    int function;  // 4, 6 or 7
  };
  using Action = void (IoFunctions::*)(int input);
  // One row of the edge-function table (§4.1 summary): functions 1 … 7.
  struct FunctionRow {
    const char* name;
    bool delayed;  // waits .05 ms on the input's timer
    Action act;
  };
  static const FunctionRow* function_row(int function);  // nullptr for 0 and the level functions

  // io_functions.cpp
  void install_hooks();
  void on_inputs_changed(std::uint32_t old_word, std::uint32_t new_word);
  void recompute_inputs();
  void reset_volatile();
  void check_enable_loss();
  void apply_events(std::uint64_t now);
  void fire_timers(std::uint64_t now);
  void update_outputs();
  std::uint32_t compose() const;
  void write_outputs();
  DriveSnapshot snapshot() const;
  OutputConfig output_config(std::size_t k) const;
  void note(core::DiagnosticLevel level, std::string text);

  // input_functions.cpp
  void dispatch_edge(int n, bool rising, std::uint64_t now);
  void dispatch_command(int n, int function, std::uint64_t now);
  void trigger(int n, int function, std::uint64_t now);
  bool motion_start(int n);
  void apply_positive(od::Handle target, od::Handle parameter);
  void capture1(int n);
  void capture2(int n);
  void count(int n);
  void move_absolute(int n);
  void quick_stop(int n);
  void move_relative(int n);
  void set_home(int n);
  void timed_move(int n, bool relative);
  void teach(int n);
  void jog_start(int n, int function);
  void jog_stop(int n);
  void cancel_all();
  void on_function_written(int n);
  std::int64_t num(od::Handle h) const { return od_.number(h); }
  void put(od::Handle h, std::int64_t v);
  // The outputs an output function owns (3611h…3614h.01 ≠ 0) and all outputs, as bits of 60FEh.01.
  // Cached by the dictionary's settings generation (issue 26: four scattered reads, twice, in every
  // step of every drive).
  struct OutputMasks {
    std::uint32_t owned = 0;
    std::uint32_t all = 0;
  };
  const OutputMasks& output_masks() const;
  const InputRecord& record(int n) const { return h_.in[static_cast<std::size_t>(n - 1)]; }
  core::helpers::DriveRef drive() { return {core_, od_, od::Origin::internal}; }

  od::ObjectDictionary& od_;
  core::DriveCore& core_;
  IoHandles h_;

  std::vector<Event> queue_;
  std::uint32_t view_ = 0;  // input word as of the events applied so far (levels for 8 and 9)
  std::array<std::optional<Timer>, 10> timers_{};
  std::optional<int> jog_owner_;
  std::uint16_t executed_ = 0;  // inputs that ran a function 4/6 move since their .01 was written
  std::uint32_t latch_ = 0;     // manual output bits (60FEh.01 bits 16…19 of function-0 outputs)
  std::uint32_t levels_ = 0;    // computed levels of owned outputs (bits 16…19)
  mutable od::SettingsCache<OutputMasks> output_masks_;
  std::vector<Diagnostic> diagnostics_;
};

}  // namespace mcemu::iofunc
