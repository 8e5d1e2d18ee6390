#include "lint/rules.hpp"

namespace mcemu::lint {

namespace {

using S = Severity;
using R = RuleId;

constexpr std::array<RuleInfo, k_rule_count> k_rules{{
    {R::cia402_enable_with_velocity_target, "cia402.enable_with_velocity_target", S::warn, "cia402", false,
     "operation enabled in profile velocity mode while the target velocity 60FFh is not 0: the axis accelerates "
     "at once",
     "write 60FFh = 0 before enabling operation, then set the target velocity",
     "drive-core.md §8.1, §4.3 (transition 4); CiA 402-2 profile velocity mode"},
    {R::cia402_setpoint_before_ack, "cia402.setpoint_before_ack", S::warn, "cia402", false,
     "new set-point (controlword bit 4 rising, bit 5 = 0) while 6041h bit 12 is still 1: the drive has not "
     "released the previous set-point and ignores this one",
     "wait until 6041h bit 12 is 0 before the next rising edge of bit 4, or set bit 5 (change set immediately)",
     "drive-core.md §7.2 (rules 2–4); CiA 402-2 set-point handshake"},
    {R::cia402_setpoint_without_edge, "cia402.setpoint_without_edge", S::warn, "cia402", false,
     "target position 607Ah changed, then a controlword with bit 4 still 1: without a rising edge the new "
     "target is never taken",
     "clear bit 4, then set it again for every new set-point",
     "drive-core.md §7.2 (rule 1: the core never clears bit 4 by itself)"},
    {R::cia402_mode_change_while_moving, "cia402.mode_change_while_moving", S::warn, "cia402", false,
     "modes of operation 6060h changed while the axis moves (6041h bit 8)",
     "bring the axis to standstill (halt, target reached) before changing 6060h",
     "drive-core.md §6.3; CiA 402-2 modes of operation (switching while moving is manufacturer specific)"},
    {R::cia402_fault_reset_held, "cia402.fault_reset_held", S::warn, "cia402", false,
     "controlword bit 7 (fault reset) held at 1: only a 0→1 edge resets a fault, and every state command needs "
     "bit 7 = 0",
     "pulse bit 7: write it 1 once, then a command with bit 7 = 0 (e.g. 0x0080, then 0x0006)",
     "drive-core.md §4.2, §11.5"},
    {R::cia402_command_ignored, "cia402.command_ignored", S::warn, "cia402", false,
     "controlword command that has no transition from the current state (it skips states) and is ignored",
     "step through the states: Shutdown 0x0006, Switch on 0x0007, Enable operation 0x000F (Fault: reset first)",
     "drive-core.md §4.2, §4.3; CiA 402-2 power drive system state machine"},
    {R::cia402_motion_in_fault, "cia402.motion_in_fault", S::warn, "cia402", false,
     "motion command while the drive is in Fault or Fault reaction active — a controlword with Enable "
     "operation, or a motion helper's target (607Ah, 60FFh ≠ 0, 6098h): it is ignored",
     "check 6041h bit 3, reset the fault with a bit 7 edge, re-enable, then command the motion",
     "drive-core.md §4.3, §11.3, §11.5"},
    {R::cia402_quick_stop_left_active, "cia402.quick_stop_left_active", S::warn, "cia402", false,
     "new set-point or homing start (controlword bit 4 rising) in Quick stop active while the controlword "
     "still commands quick stop (bit 2 = 0): ignored",
     "leave quick stop first: 0x000F (transition 16, 605Ah = 5/6) or Disable voltage, then Shutdown",
     "drive-core.md §4.3 (transitions 11, 12, 16), §4.5"},
    {R::storage_store_rate, "storage.store_rate", S::warn, "storage", true,
     "more stores to non-volatile memory per hour of drive time than the limit (max_stores_per_hour)",
     "store once after commissioning, not per cycle or per move; keep changing values in RAM",
     "persistence.md §3; faulhaber.md §9.8 (AN165: limited EEPROM write cycles)"},
    {R::storage_store_while_moving, "storage.store_while_moving", S::warn, "storage", false,
     "store to non-volatile memory while the axis moves (6041h bit 8)", "store at standstill",
     "persistence.md §1 (mcdrive.pyi StorePermanent: storing during motion may cause trajectory glitches)"},
    {R::canopen_sdo_while_stopped, "canopen.sdo_while_stopped", S::warn, "canopen", false,
     "SDO request to a node in STOPPED: the node does not answer and the client times out",
     "send NMT enter pre-operational (0x80) or start (0x01) before using SDO",
     "slcan-canopen.md §4.3; CiA 301 NMT state machine"},
    {R::canopen_sdo_overlap, "canopen.sdo_overlap", S::warn, "canopen", false,
     "SDO request before the answer to the previous one: the node has one SDO server channel",
     "wait for each SDO response (or send an abort) before the next request",
     "slcan-canopen.md §6.1; CiA 301 SDO protocol"},
    {R::canopen_pdo_mapping_while_valid, "canopen.pdo_mapping_while_valid", S::warn, "canopen", false,
     "PDO mapping written while the PDO is valid (COB-ID bit 31 = 0)",
     "set COB-ID bit 31, write sub 0 := 0, the entries, sub 0 := n, then clear bit 31",
     "slcan-canopen.md §9.2, §9.7; CiA 301 PDO mapping procedure"},
    {R::canopen_rpdo_not_operational, "canopen.rpdo_not_operational", S::warn, "canopen", false,
     "RPDO sent while the node is not OPERATIONAL (PRE-OPERATIONAL or STOPPED): ignored",
     "start the node (NMT 0x01) before sending PDOs", "slcan-canopen.md §4.3, §9.6"},
    {R::canopen_motion_without_guarding, "canopen.motion_without_guarding", S::warn, "canopen", false,
     "RPDOs drive the axis while nothing watches the master (no node guarding; the drive has no heartbeat "
     "consumer): a lost master leaves the axis on its last command",
     "configure node guarding (100Ch, 100Dh, guarding RTRs) and 6007h so that a lost master stops the axis",
     "slcan-canopen.md §5, §5.2; drive-core.md §11.6"},
    {R::canopen_traffic_before_bootup, "canopen.traffic_before_bootup", S::warn, "canopen", false,
     "frame to the node while it is INITIALISING, before its boot-up message: ignored",
     "after a reset wait for the boot-up frame (0x700 + node-id, data 00) before talking to the node",
     "slcan-canopen.md §4.3, §4.4"},
    {R::refgo_request_before_reply, "refgo.request_before_reply", S::warn, "refgo", false,
     "RefGo command sent before the reply to the previous one on the same connection",
     "wait for the prompt '>' of each reply before sending the next command", "refgo.md §2.5, §3.4"},
    {R::refgo_faster_than_drive, "refgo.faster_than_drive", S::info, "refgo", true,
     "RefGo command sooner after the previous one than a real drive answers (refgo_min_response_ms)",
     "do not depend on answers faster than the real drive's 4–76 ms (poll periods, timeouts)", "refgo.md §3.5, §14.1"},
    {R::faulhaber_request_before_reply, "faulhaber.request_before_reply", S::warn, "faulhaber", false,
     "request sent before the response to the previous one on the same connection (a collision on a 1:1 "
     "RS232 link)",
     "wait for each response before the next request", "faulhaber.md §2.1, §5"},
    {R::faulhaber_faster_than_drive, "faulhaber.faster_than_drive", S::info, "faulhaber", true,
     "request sooner after the previous one than the real drive's model answers (faulhaber_min_response_ms)",
     "do not depend on answers faster than the real drive (poll periods, timeouts)",
     "faulhaber.md §5 (response time; AN191 timeouts)"},
    {R::faulhaber_request_before_notification, "faulhaber.request_before_notification", S::warn, "faulhaber", false,
     "request sent after a controlword write that changed the statusword but before the statusword "
     "notification: its answer and the notification race",
     "after a controlword write wait for the statusword notification (command 0x05), or switch asynchronous "
     "messages off (0x2400.04 bit 17)",
     "faulhaber.md §5 (order of responses and notifications), §6"},
    {R::script_busy_loop, "script.busy_loop", S::warn, "script", false,
     "script loop that never waits: statements or drive calls without a sleep/delay starve the drive's "
     "communication",
     "wait in every loop (time.sleep_ms, sys.wait, a DELAY / timer wait in MC BASIC)",
     "scripting.md §10.1.4, §8.2; faulhaber.md §9.9"},
    {R::script_flash_write_in_loop, "script.flash_write_in_loop", S::warn, "script", true,
     "script stored to non-volatile memory again soon after its previous store (a store in a loop)",
     "store once, outside loops; keep changing values in RAM or in variables",
     "persistence.md §3; faulhaber.md §9.8 (AN165 on SAVE)"},
}};

}  // namespace

const std::array<RuleInfo, k_rule_count>& rule_table() { return k_rules; }

const RuleInfo& info(RuleId id) { return k_rules[static_cast<std::size_t>(id)]; }

std::optional<RuleId> rule_from_name(std::string_view name) {
  for (const auto& r : k_rules) {
    if (r.name == name) return r.id;
  }
  return std::nullopt;
}

std::string_view to_string(Severity s) {
  switch (s) {
    case Severity::info: return "info";
    case Severity::warn: return "warn";
    case Severity::error: break;
  }
  return "error";
}

std::optional<Severity> severity_from_string(std::string_view s) {
  if (s == "info") return Severity::info;
  if (s == "warn") return Severity::warn;
  if (s == "error") return Severity::error;
  return std::nullopt;
}

// The table is indexed by RuleId: every row must sit at its own id's position.
static_assert([] {
  for (std::size_t i = 0; i < k_rules.size(); ++i) {
    if (static_cast<std::size_t>(k_rules[i].id) != i) return false;
  }
  return true;
}());

}  // namespace mcemu::lint
