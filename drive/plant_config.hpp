// Plant and homing configuration of the drive core (drive-core.md §10.2, §9.4; models.md §4, §5).
//
// The plant's fields are model::Plant's (drive/model/model_preset.hpp), the one list of them: a
// preset gives every field, a PlantConfig replaces some (PlantOverrides) and adds the settings a
// preset has no value for. resolve_plant() merges both into PlantParams, the SI values the core
// simulates. The JSON keys of the "plant" and "homing" sections are device/plant_settings.cpp's.
#pragma once

#include <cstdint>
#include <functional>
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

// Fields of a preset's model::Plant that a config replaces, applied in the order they were set:
//   PlantOverrides o; o.set(&model::Plant::tau_th_s, 6.0).set(&model::Plant::stops_inc, StopRange{0, 9});
class PlantOverrides {
 public:
  template <typename T, typename V>
  PlantOverrides& set(T model::Plant::*field, V value) {
    edits_.push_back([field, v = T(std::move(value))](model::Plant& p) { p.*field = v; });
    return *this;
  }
  void apply(model::Plant& plant) const {
    for (const auto& edit : edits_) edit(plant);
  }
  bool empty() const { return edits_.empty(); }

 private:
  std::vector<std::function<void(model::Plant&)>> edits_;
};

struct PlantConfig {
  PlantOverrides plant;  // fields of the preset's plant replaced (they win over stroke_mm)
  // What a preset has no value for:
  std::optional<double> inertia_ctrl;  // the inertia the controller assumes; default motor + the preset's load
  double external_load = 0;            // a constant load (N·m | N)
  std::optional<double> stroke_mm;     // linear models: stops [0, stroke], power-on position in the middle
  std::vector<PositionSwitch> position_switches;
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
