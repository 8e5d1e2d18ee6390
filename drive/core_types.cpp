#include "drive/core_types.hpp"

#include <array>

namespace mcemu::core {
namespace {

constexpr std::array<std::string_view, k_fault_cause_count> k_cause_names = {
    "over_voltage",     "under_voltage",   "ack_error",           "over_temperature", "i2t",
    "abort_connection", "stroke",          "motor_communication", "sensor",           "hw_sw_enable",
    "over_current",     "external_torque", "needs_reset",         "sensor_warning"};

}  // namespace

std::string_view to_string(PdsState s) {
  switch (s) {
    case PdsState::not_ready_to_switch_on: return "not_ready_to_switch_on";
    case PdsState::switch_on_disabled: return "switch_on_disabled";
    case PdsState::ready_to_switch_on: return "ready_to_switch_on";
    case PdsState::switched_on: return "switched_on";
    case PdsState::operation_enabled: return "operation_enabled";
    case PdsState::quick_stop_active: return "quick_stop_active";
    case PdsState::fault_reaction_active: return "fault_reaction_active";
    case PdsState::fault: return "fault";
  }
  return "?";
}

std::string_view to_string(FaultCause c) { return k_cause_names[static_cast<std::size_t>(c)]; }

std::optional<FaultCause> fault_cause_from_string(std::string_view name) {
  for (std::size_t i = 0; i < k_cause_names.size(); ++i) {
    if (k_cause_names[i] == name) return static_cast<FaultCause>(i);
  }
  return std::nullopt;
}

}  // namespace mcemu::core
