// The physical plant and its control cascade (drive-core.md §10.1–§10.5, obstacles of §11.9).
//
// Contract: one step() = 1 ms = 8 sub-steps of 125 µs, exactly the equations of §10.3. The caller
// passes the demand at the end of the previous and of this step (increments, raw plant frame) and
// the torque limit of §10.4 before the motoring reduction (which the plant applies per sub-step).
// Positions are doubles in the plant's SI unit (rad or m) internally; the accessors convert to
// increments. No clock and no randomness.
#pragma once

#include <cstdint>
#include <map>
#include <optional>

#include "drive/core_types.hpp"
#include "drive/plant_config.hpp"
#include "drive/profile.hpp"

namespace mcemu::core {

struct PlantInput {
  Kinematics demand0;  // end of the previous step (inc, inc/s)
  Kinematics demand1;  // end of this step (inc, inc/s, inc/s²)
  bool torque_on = false;
  double torque_limit = 0;  // N·m or N, before the motoring reduction
  // the limit for negative torque where it differs (FAULHABER 60E1h); none: torque_limit both ways
  std::optional<double> torque_limit_negative;
};

struct PlantOutput {
  double mean_torque = 0;       // mean τ_m over the sub-steps (6078h)
  double mean_power = 0;        // mean τ_m·w (W)
  double mean_brake_power = 0;  // mean max(0, −τ_m·w) (W), regeneration (§10.11)
  double torque_raw_last = 0;   // τ_raw of the last sub-step
  double torque_limit_last = 0;
};

class Plant {
 public:
  explicit Plant(const PlantParams& params);

  // At rest at a raw position; integrator cleared.
  void reset(std::int64_t raw_inc);
  void clear_integrator() { integ_ = 0; }
  void set_inertia_ctrl(double j) { inertia_ctrl_ = j; }
  double inertia_ctrl() const { return inertia_ctrl_; }
  void set_external_load(double x) { external_load_ = x; }
  double external_load() const { return external_load_; }

  PlantOutput step(const PlantInput& in);

  double position_inc() const { return q_ * params_.inc_per_unit; }
  double velocity_inc_s() const { return w_ * params_.inc_per_unit; }
  double position() const { return q_; }
  double velocity() const { return w_; }

  ObstacleId add_obstacle(const Obstacle& o);
  void remove_obstacle(ObstacleId id);
  void clear_obstacles() { obstacles_.clear(); }

 private:
  const PlantParams& params_;
  double q_ = 0;
  double w_ = 0;
  double integ_ = 0;
  double inertia_ctrl_;
  double external_load_;
  std::map<ObstacleId, Obstacle> obstacles_;  // ordered: deterministic iteration
  ObstacleId next_id_ = 1;
};

}  // namespace mcemu::core
