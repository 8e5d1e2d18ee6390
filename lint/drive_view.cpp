#include "lint/drive_view.hpp"

#include <variant>

namespace mcemu::lint {

Pds pds_of(std::uint16_t sw) {
  // CiA 402 statusword decoding (drive-core.md §4.1): masks 0x4F / 0x6F over bits 0–6.
  switch (sw & 0x4F) {
    case 0x00: return Pds::not_ready_to_switch_on;
    case 0x40: return Pds::switch_on_disabled;
    case 0x0F: return Pds::fault_reaction_active;
    case 0x08: return Pds::fault;
    default: break;
  }
  switch (sw & 0x6F) {
    case 0x21: return Pds::ready_to_switch_on;
    case 0x23: return Pds::switched_on;
    case 0x27: return Pds::operation_enabled;
    case 0x07: return Pds::quick_stop_active;
    default: break;
  }
  return Pds::not_ready_to_switch_on;  // not a CiA 402 pattern: treated as "nothing to judge"
}

std::string_view to_string(Pds s) {
  switch (s) {
    case Pds::not_ready_to_switch_on: return "Not ready to switch on";
    case Pds::switch_on_disabled: return "Switch on disabled";
    case Pds::ready_to_switch_on: return "Ready to switch on";
    case Pds::switched_on: return "Switched on";
    case Pds::operation_enabled: return "Operation enabled";
    case Pds::quick_stop_active: return "Quick stop active";
    case Pds::fault_reaction_active: return "Fault reaction active";
    case Pds::fault: break;
  }
  return "Fault";
}

Command command_of(std::uint16_t cw) {
  if ((cw & 0x0002) == 0) return Command::disable_voltage;
  if ((cw & 0x0004) == 0) return Command::quick_stop;
  if ((cw & 0x0001) == 0) return Command::shutdown;
  if ((cw & 0x0008) == 0) return Command::switch_on;
  return Command::enable_operation;
}

std::string_view to_string(Command c) {
  switch (c) {
    case Command::shutdown: return "Shutdown";
    case Command::switch_on: return "Switch on";
    case Command::enable_operation: return "Enable operation";
    case Command::disable_voltage: return "Disable voltage";
    case Command::quick_stop: break;
  }
  return "Quick stop";
}

Pds target_of(Command c, Pds from) {
  switch (c) {
    case Command::shutdown: return Pds::ready_to_switch_on;
    case Command::switch_on: return Pds::switched_on;
    case Command::enable_operation: return Pds::operation_enabled;
    case Command::disable_voltage: return Pds::switch_on_disabled;
    case Command::quick_stop: break;
  }
  return from == Pds::operation_enabled || from == Pds::quick_stop_active ? Pds::quick_stop_active
                                                                          : Pds::switch_on_disabled;
}

void DriveView::apply(const OdWrite& w) {
  statusword = w.statusword_after;
  mode_display = w.mode_after;
  if (!accepted(w.result) || w.sub != 0) return;
  switch (w.index) {
    case 0x6040: {
      const auto cw = static_cast<std::uint16_t>(w.value);
      if ((cw & 0x0010) && !(controlword & 0x0010)) target_changed = false;
      controlword = cw;
      break;
    }
    case 0x6060: mode_command = static_cast<std::int8_t>(w.value); break;
    case 0x607A: target_changed = true; break;
    case 0x60FF: target_velocity = w.value; break;
    default: break;
  }
}

void DriveView::apply(const CoreEvent& e) {
  if (const auto* s = std::get_if<core::StatuswordChanged>(&e.event)) {
    statusword = s->new_value;
  } else if (const auto* m = std::get_if<core::ModeDisplayChanged>(&e.event)) {
    mode_display = m->mode;
  }
}

void DriveView::apply(const PowerOn& p) {
  statusword = p.statusword;
  controlword = p.controlword;
  mode_display = 0;  // 6061h = 0 at power on (drive-core.md §4.4)
  mode_command = p.mode;
  target_velocity = p.target_velocity;
  target_changed = false;
}

}  // namespace mcemu::lint
