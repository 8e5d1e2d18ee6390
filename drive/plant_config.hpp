// Plant and homing configuration of the drive core (drive-core.md §10.2, §9.4; models.md §4, §5).
//
// PlantConfig holds the overrides the server maps from the "plant" and "homing" sections of
// --config (every field optional; absent = the model preset's value). resolve_plant() merges them
// with the preset into PlantParams, the SI values the core simulates. JSON keys (same names in
// the "plant" object unless noted):
//   torque_peak, torque_cont, inertia_motor, inertia_load, inertia_ctrl, viscous, coulomb,
//   no_load_speed (rpm | m/s), velocity_bandwidth_hz, accel_feedforward, external_load,
//   stops ([min_inc, max_inc] or null), stroke_mm (MCFLAT/MCSHORT), power_on_position (inc),
//   position_switches ([{"input": n, "from_inc": a, "to_inc": b}, …]), moving_threshold
//   (rpm | mm/s), following_error_limit (inc, 0 = none), P_idle, P_cu (W), R_th (K/W), tau_th (s),
//   temperature_available, supply_nominal_V, uv_V, ov_V, hw_enable_fitted,
//   rotary_accel_unit ([num, den] motor rev/s² per unit, default [1, 36]),
//   noise ({"enabled": false, "inc": 2, "seed": 1}), regen ({"enabled": false, "capacitance_F": 0.001});
//   "homing": {"max_search_ms": 60000, "enable_method_18": false}.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "drive/model/model_preset.hpp"

namespace mcemu::core {

using StopRange = std::pair<std::int64_t, std::int64_t>;  // [min, max] raw increments

struct PositionSwitch {
  int input = 1;  // IN n, 1…10; must have a pin on the model
  std::int64_t from_inc = 0;
  std::int64_t to_inc = 0;
};

// Optional measurement noise (§10.8): a uniform integer in [−inc, +inc] added to the reported
// 6063h from splitmix64(seed); 606Ch is derived from the noisy values.
struct NoiseConfig {
  bool enabled = false;
  std::int64_t inc = 2;
  std::uint64_t seed = 1;
};

// Optional regeneration into the DC link (§10.11).
struct RegenConfig {
  bool enabled = false;
  double capacitance_f = 0.001;
};

struct HomingConfig {
  std::int64_t max_search_ms = 60000;
  bool enable_method_18 = false;
};

struct PlantConfig {
  std::optional<double> torque_peak;
  std::optional<double> torque_cont;
  std::optional<double> inertia_motor;
  std::optional<double> inertia_load;
  std::optional<double> inertia_ctrl;
  std::optional<double> viscous;
  std::optional<double> coulomb;
  std::optional<double> no_load_speed;
  std::optional<double> velocity_bandwidth_hz;
  std::optional<double> accel_feedforward;
  std::optional<double> external_load;
  std::optional<std::optional<StopRange>> stops;  // outer: given; inner nullopt: "stops": null
  std::optional<double> stroke_mm;
  std::optional<std::int64_t> power_on_position;
  std::vector<PositionSwitch> position_switches;
  std::optional<double> moving_threshold;
  std::optional<std::int64_t> following_error_limit;
  std::optional<double> p_idle_w;
  std::optional<double> p_cu_w;
  std::optional<double> r_th_k_per_w;
  std::optional<double> tau_th_s;
  std::optional<bool> temperature_available;
  std::optional<double> supply_nominal_v;
  std::optional<double> supply_uv_v;
  std::optional<double> supply_ov_v;
  std::optional<bool> hw_enable_fitted;
  std::optional<std::pair<std::uint64_t, std::uint64_t>> rotary_accel_unit;
  NoiseConfig noise;
  RegenConfig regen;
  HomingConfig homing;
};

// The resolved values, SI units (rotary: rad, N·m, kg·m²; linear: m, N, kg).
struct PlantParams {
  model::Kind kind = model::Kind::rotary;
  double inc_per_unit = 0;  // increments per rad (rotary) or per m (linear)
  double torque_peak = 0;
  double torque_cont = 0;
  double inertia = 0;                 // plant: motor + load
  double inertia_ctrl = 0;            // what the controller assumes
  bool inertia_ctrl_from_od = false;  // RABBIT: (3300h.07 + 3301h.04) / 1000 kg, unless configured
  double viscous = 0;
  double coulomb = 0;
  double no_load_speed = 0;  // rad/s or m/s
  double velocity_bandwidth_hz = 150;
  double accel_feedforward = 0.9;
  double external_load = 0;
  std::optional<StopRange> stops_inc;
  std::vector<PositionSwitch> position_switches;
  std::int64_t power_on_position_inc = 0;
  double moving_threshold_inc_s = 0;
  std::int64_t following_error_limit_inc = 0;
  bool absolute_encoder = true;
  double p_idle_w = 2;
  double p_cu_w = 40;
  double r_th_k_per_w = 3;
  double tau_th_s = 600;
  bool temperature_available = true;
  double supply_nominal_v = 48;
  double supply_uv_v = 18;
  double supply_ov_v = 60;
  bool hw_enable_fitted = false;
  int hw_enable_input = 0;
  std::uint64_t accel_unit_num = 1;
  std::uint64_t accel_unit_den = 36;
  NoiseConfig noise;
  RegenConfig regen;
  HomingConfig homing;
};

// Merges preset and config. Throws std::invalid_argument with one line naming the offending key
// (start-up error): a position switch on an input without a pin, hw_enable_fitted on a model whose
// HW enable is a power pin, stroke_mm on a rotary model, a non-positive inertia or bandwidth.
PlantParams resolve_plant(const model::ModelPreset& preset, const PlantConfig& config);

}  // namespace mcemu::core
