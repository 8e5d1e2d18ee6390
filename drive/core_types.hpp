// Vocabulary of the drive core (drive-core.md §1.5): PDS states, fault causes, power-on state and
// obstacles. Plain values; no behaviour beyond naming.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace mcemu::core {

// CiA 402 power drive system states (drive-core.md §4.1).
enum class PdsState : std::uint8_t {
  not_ready_to_switch_on,
  switch_on_disabled,
  ready_to_switch_on,
  switched_on,
  operation_enabled,
  quick_stop_active,
  fault_reaction_active,
  fault
};

// The fault and warning causes of drive-core.md §11.1, by their API names.
enum class FaultCause : std::uint8_t {
  over_voltage,
  under_voltage,
  ack_error,
  over_temperature,
  i2t,
  abort_connection,
  stroke,
  motor_communication,
  sensor,
  hw_sw_enable,
  over_current,
  external_torque,
  needs_reset,
  sensor_warning
};
inline constexpr int k_fault_cause_count = 14;

// What a power cycle keeps outside the OD (drive-core.md §1.5, persistence.md §8).
struct PowerOnState {
  std::optional<std::int64_t> raw_position_inc;  // plant position; none → the model's power-on position
  std::int64_t home_offset_inc = 0;              // stored home offset; used by absolute models (§10.10)
};

// A temporary mechanical stop at a raw position (drive-core.md §11.9). side = +1 blocks motion in
// the positive direction (the axis comes from below), -1 in the negative direction.
struct Obstacle {
  std::int64_t position_inc = 0;
  int side = +1;
};
using ObstacleId = std::uint32_t;

std::string_view to_string(PdsState s);
std::string_view to_string(FaultCause c);
// nullopt for an unknown name; names are the API names above ("under_voltage").
std::optional<FaultCause> fault_cause_from_string(std::string_view name);

}  // namespace mcemu::core
