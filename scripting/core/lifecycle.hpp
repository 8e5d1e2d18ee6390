// The script life cycle of scripting.md §3 as a pure table: a trigger in a state gives the next
// state and the actions the engine carries out, in this order: terminate the running engine,
// replace the source, launch a new engine, freeze or thaw. Also the mapping of the control objects
// (3500h.02, 1F51h.01) and of `codeAct` (web.md §6.2) onto triggers.
//
// Pure; the engine (scripting/engine.hpp) owns the processes and applies the actions.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace mcemu::scripting {

enum class RunState : std::uint8_t { off, run, brk };
std::string_view to_string(RunState s);  // "OFF", "RUN", "BRK"
// 3500h.02 / 1F51h.01 read value: 0 stopped, 1 running, 2 paused.
std::int64_t run_control_value(RunState s);

enum class Trigger : std::uint8_t {
  start,          // 3500h.02 := 1 while stopped, 1F51h.01 := 1, autostart: only from OFF
  restart,        // codeAct=3, RUN/Restart buttons, 1F51h.01 := 2, POST …/start: start, or stop + start
  stop,           // codeAct=4, 3500h.02 := 0, 1F51h.01 := 0, POST …/stop, script.kill
  pause,          // codeAct=1, 3500h.02 := 2
  resume,         // codeAct=2, 3500h.02 := 1 while paused
  finished,       // end of the program, sys.exit(), an uncaught exception, a compile error
  engine_died,    // the process ended without reporting the end
  upload,         // a valid upload replaces the source
  delete_script,  // 1F51h.01 := 3: the placeholder in RAM
  factory_reset,  // 1011h: the placeholder
  power_cycle,    // power loss: the stored script is loaded; autostart is a separate call
  reset_node,     // NMT reset node: as power_cycle, without the UDP start-up block
};

enum class SourceChange : std::uint8_t { none, uploaded, placeholder, stored };

struct Decision {
  RunState next = RunState::off;
  bool terminate = false;  // stop the running/paused engine (nothing else of §3.3 differs)
  SourceChange source = SourceChange::none;
  bool launch = false;  // "code: starting", a new engine, compile after 100 ms
  bool freeze = false;  // SIGSTOP
  bool thaw = false;    // SIGCONT
  bool changed() const { return terminate || source != SourceChange::none || launch || freeze || thaw; }
};

Decision decide(RunState state, Trigger trigger);

// 3500h.02 := v (v already range-checked by the OD: 0, 1, 2).
std::optional<Trigger> run_control_trigger(std::int64_t value, RunState state);
// 1F51h.01 := v (0, 1, 2, 3).
std::optional<Trigger> program_control_trigger(std::int64_t value);
// GET /program.html?codeAct=N for N = 1…4 (5/6 write 3500h.04 and are not life-cycle triggers).
std::optional<Trigger> code_act_trigger(int code_act);

}  // namespace mcemu::scripting
