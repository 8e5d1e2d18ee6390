#include "lint/cia402_rules.hpp"

#include <cstdio>
#include <string>

namespace mcemu::lint {

namespace {

std::string hex4(std::uint16_t v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%04X", v);
  return buf;
}

bool faulted(Pds s) { return s == Pds::fault || s == Pds::fault_reaction_active; }

// States in which a command without a transition is simply not acted on (drive-core.md §4.3).
// OE is left out: every command has a transition there (some wait for a ramp); NRTSO and FRA
// ignore everything by design, Fault is motion_in_fault's business.
bool judged_for_ignored(Pds s) {
  return s == Pds::switch_on_disabled || s == Pds::ready_to_switch_on || s == Pds::switched_on ||
         s == Pds::quick_stop_active;
}

void on_controlword(const OdWrite& w, const DriveView& v, const At& at, Reporter& rep) {
  const auto cw = static_cast<std::uint16_t>(w.value);
  const auto prev = v.controlword;
  const Pds before = v.state();
  const Pds after = pds_of(w.statusword_after);
  const bool reset_bit = (cw & 0x0080) != 0;
  const bool rising4 = (cw & 0x0010) && !(prev & 0x0010);
  const Command cmd = command_of(cw);

  // Motion while faulted is a finding also when a helper asked for it (nothing moves).
  if (faulted(before) && !reset_bit && cmd == Command::enable_operation) {
    rep.fire(RuleId::cia402_motion_in_fault, at, [&] {
      return "controlword " + hex4(cw) + " (Enable operation) in " + std::string(to_string(before)) + ": ignored";
    });
  }
  if (w.helper) return;

  if (reset_bit && (prev & 0x0080)) {
    rep.fire(RuleId::cia402_fault_reset_held, at, [&] {
      return "controlword " + hex4(cw) + " after " + hex4(prev) + ": bit 7 stayed 1 (no edge) in " +
             std::string(to_string(before));
    });
  }
  if (reset_bit) return;

  if (judged_for_ignored(before) && after == before && target_of(cmd, before) != before) {
    rep.fire(RuleId::cia402_command_ignored, at, [&] {
      return "controlword " + hex4(cw) + " (" + std::string(to_string(cmd)) + ") in " + std::string(to_string(before)) +
             " is ignored";
    });
  }
  // 6061h follows a 6060h write only in the next step on a MovingCap (drive-core.md §6.3): the mode
  // last written counts as well as the one displayed.
  if ((before == Pds::ready_to_switch_on || before == Pds::switched_on) && after == Pds::operation_enabled &&
      (w.mode_after == 3 || v.mode_command == 3) && v.target_velocity != 0) {
    rep.fire(RuleId::cia402_enable_with_velocity_target, at, [&] {
      return "controlword " + hex4(cw) +
             " enabled operation in profile velocity with 60FFh = " + std::to_string(v.target_velocity);
    });
  }
  if (before == Pds::operation_enabled && v.mode_display == 1) {
    if (rising4 && !(cw & 0x0020) && (v.statusword & 0x1000)) {
      rep.fire(RuleId::cia402_setpoint_before_ack, at, [&] {
        return "controlword " + hex4(cw) + " raised bit 4 while 6041h = " + hex4(v.statusword) + " (bit 12 set)";
      });
    }
    if ((cw & 0x0010) && (prev & 0x0010) && v.target_changed) {
      rep.fire(RuleId::cia402_setpoint_without_edge, at, [&] {
        return "controlword " + hex4(cw) + " after " + hex4(prev) + ": bit 4 stayed 1 after 607Ah changed";
      });
    }
  }
  if (before == Pds::quick_stop_active && cmd == Command::quick_stop && rising4) {
    rep.fire(RuleId::cia402_quick_stop_left_active, at,
             [&] { return "controlword " + hex4(cw) + " raised bit 4 with quick stop still commanded (bit 2 = 0)"; });
  }
}

}  // namespace

void cia402_rules(const OdWrite& w, const DriveView& v, const At& at, Reporter& rep) {
  if (!accepted(w.result) || w.sub != 0 || w.origin == od::Origin::internal) return;
  switch (w.index) {
    case 0x6040: on_controlword(w, v, at, rep); break;
    case 0x6060:
      if (!w.helper && w.value != v.mode_command && v.moving()) {
        rep.fire(RuleId::cia402_mode_change_while_moving, at, [&] {
          return "6060h := " + std::to_string(w.value) + " (was " + std::to_string(v.mode_command) +
                 ") while 6041h = " + hex4(v.statusword) + " (bit 8: moving)";
        });
      }
      break;
    case 0x607A:
    case 0x60FF:
    case 0x6098:
      // A motion helper (RefGo G/JP/REF, mcdrive Go…) whose AUTOENABLE found the drive faulted
      // still writes its target: the command is lost (drive-core.md §12 AUTOENABLE).
      if (w.helper && faulted(v.state()) && !(w.index == 0x60FF && w.value == 0)) {
        rep.fire(RuleId::cia402_motion_in_fault, at, [&] {
          char buf[16];
          std::snprintf(buf, sizeof buf, "%04Xh", w.index);
          return "motion command (" + std::string(buf) + " := " + std::to_string(w.value) + ") in " +
                 std::string(to_string(v.state())) + ": ignored";
        });
      }
      break;
    default: break;
  }
}

}  // namespace mcemu::lint
