#include "drive/plant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mcemu::core {
namespace {

constexpr int k_substeps = 8;
constexpr double k_h = 0.001 / k_substeps;

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

}  // namespace

Plant::Plant(const PlantParams& params)
    : params_(params), inertia_ctrl_(params.inertia_ctrl), external_load_(params.external_load) {}

void Plant::reset(std::int64_t raw_inc) {
  q_ = static_cast<double>(raw_inc) / params_.inc_per_unit;
  w_ = 0;
  integ_ = 0;
}

ObstacleId Plant::add_obstacle(const Obstacle& o) {
  const ObstacleId id = next_id_++;
  obstacles_[id] = o;
  return id;
}

void Plant::remove_obstacle(ObstacleId id) { obstacles_.erase(id); }

PlantOutput Plant::step(const PlantInput& in) {
  const double kq = params_.inc_per_unit;
  const double wv = 2 * std::numbers::pi * params_.velocity_bandwidth_hz;
  const double kv = inertia_ctrl_ * wv;
  const double ki = kv * wv / 4;
  const double kp = wv / 5;
  const double m = params_.inertia;
  const double c = params_.coulomb;
  const double b = params_.viscous;
  const double w_eps = params_.kind == model::Kind::rotary ? 1e-4 : 1e-6;
  const double h_m = k_h / m;  // one division per step, not one per sub-step (the loop's critical path)
  const double pd0 = in.demand0.p / kq;
  const double pd1 = in.demand1.p / kq;
  const double vd0 = in.demand0.v / kq;
  const double vd1 = in.demand1.v / kq;
  const double ad1 = in.demand1.a / kq;
  double stop_min = -INFINITY;
  double stop_max = INFINITY;
  if (params_.stops_inc) {
    stop_min = static_cast<double>(params_.stops_inc->first) / kq;
    stop_max = static_cast<double>(params_.stops_inc->second) / kq;
  }
  PlantOutput out;
  double torque_sum = 0;
  double power_sum = 0;
  double brake_sum = 0;
  for (int s = 1; s <= k_substeps; ++s) {
    double tau_m = 0;
    if (in.torque_on) {
      const double f = static_cast<double>(s - 1) / k_substeps;
      const double p_ref = pd0 + f * (pd1 - pd0);
      const double v_ff = vd0 + f * (vd1 - vd0);
      const double e_p = p_ref - q_;
      const double w_cmd = v_ff + kp * e_p;
      const double e_v = w_cmd - w_;
      const double tau_raw = params_.accel_feedforward * inertia_ctrl_ * ad1 + kv * e_v + integ_;
      double tau_lim = (in.torque_limit_negative && tau_raw < 0) ? *in.torque_limit_negative : in.torque_limit;
      if (tau_raw * w_ > 0 && params_.no_load_speed > 0) {
        tau_lim = std::min(tau_lim, params_.torque_peak * std::max(0.0, 1 - std::fabs(w_) / params_.no_load_speed));
      }
      tau_m = std::clamp(tau_raw, -tau_lim, tau_lim);
      if (std::fabs(tau_raw) <= tau_lim || sign_of(e_v) != sign_of(tau_raw)) integ_ += ki * e_v * k_h;
      out.torque_raw_last = tau_raw;
      out.torque_limit_last = tau_lim;
    } else {
      integ_ = 0;
    }
    const double tau_d = tau_m + external_load_;
    double w_next;
    if (std::fabs(w_) > w_eps) {
      w_next = w_ + h_m * (tau_d - b * w_ - c * sign_of(w_));
      if (sign_of(w_next) != sign_of(w_)) w_next = 0;
    } else {
      w_next = std::fabs(tau_d) <= c ? 0.0 : h_m * (tau_d - c * sign_of(tau_d));
    }
    double q_next = q_ + k_h * w_next;
    if (q_next > stop_max) {
      q_next = stop_max;
      w_next = std::min(w_next, 0.0);
    }
    if (q_next < stop_min) {
      q_next = stop_min;
      w_next = std::max(w_next, 0.0);
    }
    for (const auto& [id, o] : obstacles_) {
      const double x = static_cast<double>(o.position_inc) / kq;
      if (o.side > 0 && q_ <= x && q_next > x) {
        q_next = x;
        w_next = std::min(w_next, 0.0);
      } else if (o.side < 0 && q_ >= x && q_next < x) {
        q_next = x;
        w_next = std::max(w_next, 0.0);
      }
    }
    torque_sum += tau_m;
    power_sum += tau_m * w_next;
    brake_sum += std::max(0.0, -tau_m * w_next);
    q_ = q_next;
    w_ = w_next;
  }
  out.mean_torque = torque_sum / k_substeps;
  out.mean_power = power_sum / k_substeps;
  out.mean_brake_power = brake_sum / k_substeps;
  return out;
}

}  // namespace mcemu::core
