#include "drive/plant_config.hpp"

#include <algorithm>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mcemu::core {

PlantParams resolve_plant(const model::ModelPreset& preset, const PlantConfig& c) {
  const model::Plant& m = preset.plant;
  const bool rotary = preset.kind == model::Kind::rotary;
  PlantParams p;
  p.kind = preset.kind;
  p.inc_per_unit = rotary ? static_cast<double>(preset.encoder_inc) / (2 * std::numbers::pi) : 1e6;
  p.torque_peak = c.torque_peak.value_or(m.torque_peak);
  p.torque_cont = c.torque_cont.value_or(m.torque_cont);
  const double motor = c.inertia_motor.value_or(m.inertia_motor);
  const double load = c.inertia_load.value_or(m.inertia_load);
  p.inertia = motor + load;
  if (c.inertia_ctrl) {
    p.inertia_ctrl = *c.inertia_ctrl;
  } else {
    p.inertia_ctrl = motor + m.inertia_load;
    p.inertia_ctrl_from_od = preset.is_rabbit();
  }
  p.viscous = c.viscous.value_or(m.viscous);
  p.coulomb = c.coulomb.value_or(m.coulomb);
  const double no_load = c.no_load_speed.value_or(m.no_load_speed);
  p.no_load_speed = rotary ? no_load * 2 * std::numbers::pi / 60.0 : no_load;
  p.velocity_bandwidth_hz = c.velocity_bandwidth_hz.value_or(m.velocity_bandwidth_hz);
  p.accel_feedforward = c.accel_feedforward.value_or(m.accel_feedforward);
  p.external_load = c.external_load.value_or(0.0);
  p.stops_inc = m.stops_inc;
  p.power_on_position_inc = m.power_on_position_inc;
  if (c.stroke_mm) {
    if (rotary) throw std::invalid_argument("plant.stroke_mm applies to linear models only (MCFLAT, MCSHORT)");
    if (*c.stroke_mm <= 0) throw std::invalid_argument("plant.stroke_mm must be positive");
    const auto stroke = static_cast<std::int64_t>(*c.stroke_mm * 1000.0);
    p.stops_inc = StopRange{0, stroke};
    p.power_on_position_inc = stroke / 2;
  }
  if (c.stops) p.stops_inc = *c.stops;
  if (p.stops_inc && p.stops_inc->first > p.stops_inc->second) {
    throw std::invalid_argument("plant.stops: min is above max");
  }
  if (c.power_on_position) p.power_on_position_inc = *c.power_on_position;
  for (const auto& sw : c.position_switches) {
    if (std::find(preset.input_pins.begin(), preset.input_pins.end(), sw.input) == preset.input_pins.end()) {
      throw std::invalid_argument("plant.position_switches: input " + std::to_string(sw.input) +
                                  " has no pin on model " + preset.name);
    }
  }
  p.position_switches = c.position_switches;
  const double moving = c.moving_threshold.value_or(m.moving_threshold);
  p.moving_threshold_inc_s = rotary ? moving * static_cast<double>(preset.encoder_inc) / 60.0 : moving * 1000.0;
  p.following_error_limit_inc = c.following_error_limit.value_or(m.following_error_limit_inc);
  p.absolute_encoder = m.absolute_encoder;
  p.p_idle_w = c.p_idle_w.value_or(m.p_idle_w);
  p.p_cu_w = c.p_cu_w.value_or(m.p_cu_w);
  p.r_th_k_per_w = c.r_th_k_per_w.value_or(m.r_th_k_per_w);
  p.tau_th_s = c.tau_th_s.value_or(m.tau_th_s);
  p.temperature_available = c.temperature_available.value_or(m.temperature_available);
  p.supply_nominal_v = c.supply_nominal_v.value_or(m.supply_nominal_v);
  p.supply_uv_v = c.supply_uv_v.value_or(m.supply_uv_v);
  p.supply_ov_v = c.supply_ov_v.value_or(m.supply_ov_v);
  p.hw_enable_fitted = c.hw_enable_fitted.value_or(m.hw_enable_fitted);
  p.hw_enable_input = m.hw_enable_input;
  if (p.hw_enable_fitted && p.hw_enable_input == 0) {
    throw std::invalid_argument("plant.hw_enable_fitted: the HW enable of model " + preset.name +
                                " is a power pin, not an input");
  }
  const auto unit = c.rotary_accel_unit.value_or(std::pair<std::uint64_t, std::uint64_t>{
      static_cast<std::uint64_t>(m.rotary_accel_unit_num), static_cast<std::uint64_t>(m.rotary_accel_unit_den)});
  if (unit.first == 0 || unit.second == 0) throw std::invalid_argument("plant.rotary_accel_unit: zero term");
  p.accel_unit_num = unit.first;
  p.accel_unit_den = unit.second;
  p.homing = c.homing;
  p.noise = c.noise;
  if (p.noise.inc < 0) throw std::invalid_argument("plant.noise.inc must not be negative");
  p.regen = c.regen;
  if (p.regen.enabled && p.regen.capacitance_f <= 0) {
    throw std::invalid_argument("plant.regen.capacitance_F must be positive");
  }
  if (p.inertia <= 0 || p.inertia_ctrl <= 0) throw std::invalid_argument("plant inertia must be positive");
  if (p.velocity_bandwidth_hz <= 0) throw std::invalid_argument("plant.velocity_bandwidth_hz must be positive");
  if (p.torque_peak <= 0) throw std::invalid_argument("plant.torque_peak must be positive");
  if (p.r_th_k_per_w <= 0 || p.tau_th_s <= 0) throw std::invalid_argument("plant thermal constants must be positive");
  return p;
}

}  // namespace mcemu::core
