// The rule table of the master lint (docs/lint.md §4): one row per rule — its id (the config
// key), default severity, family, whether it compares drive-time intervals, what to do instead and
// the section of the manual or standard it rests on.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace mcemu::lint {

enum class Severity : std::uint8_t { info, warn, error };

enum class RuleId : std::uint8_t {
  cia402_enable_with_velocity_target,
  cia402_setpoint_before_ack,
  cia402_setpoint_without_edge,
  cia402_mode_change_while_moving,
  cia402_fault_reset_held,
  cia402_command_ignored,
  cia402_motion_in_fault,
  cia402_quick_stop_left_active,
  storage_store_rate,
  storage_store_while_moving,
  canopen_sdo_while_stopped,
  canopen_sdo_overlap,
  canopen_pdo_mapping_while_valid,
  canopen_rpdo_not_operational,
  canopen_motion_without_guarding,
  canopen_traffic_before_bootup,
  refgo_request_before_reply,
  refgo_faster_than_drive,
  faulhaber_request_before_reply,
  faulhaber_faster_than_drive,
  faulhaber_request_before_notification,
  script_busy_loop,
  script_flash_write_in_loop,
};
inline constexpr std::size_t k_rule_count = 23;

struct RuleInfo {
  RuleId id;
  std::string_view name;  // "cia402.command_ignored": the key of "lint": {"rules": {…}}
  Severity severity;      // default
  std::string_view family;
  bool timing;               // compares drive-time intervals (off with "timing": false)
  std::string_view summary;  // what the rule reports
  std::string_view advice;   // what to do instead
  std::string_view reference;
};

const std::array<RuleInfo, k_rule_count>& rule_table();
const RuleInfo& info(RuleId id);
std::optional<RuleId> rule_from_name(std::string_view name);

std::string_view to_string(Severity s);  // "info", "warn", "error"
std::optional<Severity> severity_from_string(std::string_view s);

}  // namespace mcemu::lint
