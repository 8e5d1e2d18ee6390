#include "drive/plant_config.hpp"

#include <algorithm>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mcemu::core {

PlantParams resolve_plant(const model::ModelPreset& preset, const PlantConfig& c) {
  const bool rotary = preset.kind == model::Kind::rotary;
  model::Plant m = preset.plant;
  if (c.stroke_mm) {
    if (rotary) throw std::invalid_argument("plant.stroke_mm applies to linear models only (MCFLAT, MCSHORT)");
    if (*c.stroke_mm <= 0) throw std::invalid_argument("plant.stroke_mm must be positive");
    const auto stroke = static_cast<std::int64_t>(*c.stroke_mm * 1000.0);
    m.stops_inc = StopRange{0, stroke};
    m.power_on_position_inc = stroke / 2;
  }
  c.plant.apply(m);
  PlantParams p;
  p.kind = preset.kind;
  p.inc_per_unit = rotary ? static_cast<double>(preset.encoder_inc) / (2 * std::numbers::pi) : 1e6;
  p.torque_peak = m.torque_peak;
  p.torque_cont = m.torque_cont;
  p.inertia = m.inertia_motor + m.inertia_load;
  if (c.inertia_ctrl) {
    p.inertia_ctrl = *c.inertia_ctrl;
  } else {
    p.inertia_ctrl = m.inertia_motor + preset.plant.inertia_load;  // a configured load is unknown to it
    p.inertia_ctrl_from_od = preset.is_rabbit();
  }
  p.viscous = m.viscous;
  p.coulomb = m.coulomb;
  p.no_load_speed = rotary ? m.no_load_speed * 2 * std::numbers::pi / 60.0 : m.no_load_speed;
  p.velocity_bandwidth_hz = m.velocity_bandwidth_hz;
  p.accel_feedforward = m.accel_feedforward;
  p.external_load = c.external_load;
  p.stops_inc = m.stops_inc;
  if (p.stops_inc && p.stops_inc->first > p.stops_inc->second) {
    throw std::invalid_argument("plant.stops: min is above max");
  }
  p.power_on_position_inc = m.power_on_position_inc;
  for (const auto& sw : c.position_switches) {
    if (std::find(preset.input_pins.begin(), preset.input_pins.end(), sw.input) == preset.input_pins.end()) {
      throw std::invalid_argument("plant.position_switches: input " + std::to_string(sw.input) +
                                  " has no pin on model " + preset.name);
    }
  }
  p.position_switches = c.position_switches;
  p.moving_threshold_inc_s =
      rotary ? m.moving_threshold * static_cast<double>(preset.encoder_inc) / 60.0 : m.moving_threshold * 1000.0;
  p.following_error_limit_inc = m.following_error_limit_inc;
  p.absolute_encoder = m.absolute_encoder;
  p.p_idle_w = m.p_idle_w;
  p.p_cu_w = m.p_cu_w;
  p.r_th_k_per_w = m.r_th_k_per_w;
  p.tau_th_s = m.tau_th_s;
  p.temperature_available = m.temperature_available;
  p.supply_nominal_v = m.supply_nominal_v;
  p.supply_uv_v = m.supply_uv_v;
  p.supply_ov_v = m.supply_ov_v;
  p.hw_enable_fitted = m.hw_enable_fitted;
  p.hw_enable_input = m.hw_enable_input;
  if (p.hw_enable_fitted && p.hw_enable_input == 0) {
    throw std::invalid_argument("plant.hw_enable_fitted: the HW enable of model " + preset.name +
                                " is a power pin, not an input");
  }
  if (m.rotary_accel_unit_num <= 0 || m.rotary_accel_unit_den <= 0) {
    throw std::invalid_argument("plant.rotary_accel_unit: zero term");
  }
  p.accel_unit_num = static_cast<std::uint64_t>(m.rotary_accel_unit_num);
  p.accel_unit_den = static_cast<std::uint64_t>(m.rotary_accel_unit_den);
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
