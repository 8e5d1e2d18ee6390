#include "scripting/core/lifecycle.hpp"

namespace mcemu::scripting {

std::string_view to_string(RunState s) {
  switch (s) {
    case RunState::off: return "OFF";
    case RunState::run: return "RUN";
    case RunState::brk: return "BRK";
  }
  return "OFF";
}

std::int64_t run_control_value(RunState s) {
  switch (s) {
    case RunState::off: return 0;
    case RunState::run: return 1;
    case RunState::brk: return 2;
  }
  return 0;
}

Decision decide(RunState state, Trigger trigger) {
  const bool active = state != RunState::off;
  Decision d;
  d.next = state;
  switch (trigger) {
    case Trigger::start:
      if (!active) {
        d.next = RunState::run;
        d.launch = true;
      }
      break;
    case Trigger::restart:
      d.next = RunState::run;
      d.terminate = active;
      d.launch = true;
      break;
    case Trigger::stop:
    case Trigger::finished:
    case Trigger::engine_died:
      d.next = RunState::off;
      d.terminate = active;
      break;
    case Trigger::pause:
      if (state == RunState::run) {
        d.next = RunState::brk;
        d.freeze = true;
      }
      break;
    case Trigger::resume:
      if (state == RunState::brk) {
        d.next = RunState::run;
        d.thaw = true;
      }
      break;
    case Trigger::upload:
      d.next = RunState::off;
      d.terminate = active;
      d.source = SourceChange::uploaded;
      break;
    case Trigger::delete_script:
    case Trigger::factory_reset:
      d.next = RunState::off;
      d.terminate = active;
      d.source = SourceChange::placeholder;
      break;
    case Trigger::power_cycle:
    case Trigger::reset_node:
      d.next = RunState::off;
      d.terminate = active;
      d.source = SourceChange::stored;
      break;
  }
  return d;
}

std::optional<Trigger> run_control_trigger(std::int64_t value, RunState state) {
  switch (value) {
    case 0: return Trigger::stop;
    case 1: return state == RunState::brk ? Trigger::resume : Trigger::start;
    case 2: return Trigger::pause;
    default: return std::nullopt;
  }
}

std::optional<Trigger> program_control_trigger(std::int64_t value) {
  switch (value) {
    case 0: return Trigger::stop;
    case 1: return Trigger::start;
    case 2: return Trigger::restart;
    case 3: return Trigger::delete_script;
    default: return std::nullopt;
  }
}

std::optional<Trigger> code_act_trigger(int code_act) {
  switch (code_act) {
    case 1: return Trigger::pause;
    case 2: return Trigger::resume;
    case 3: return Trigger::restart;
    case 4: return Trigger::stop;
    default: return std::nullopt;
  }
}

}  // namespace mcemu::scripting
