#include "drive/thermal.hpp"

#include <algorithm>

namespace mcemu::core {
namespace {

constexpr double k_dt = 0.001;

}  // namespace

void Thermal::reset(double ambient_c) {
  t_ = ambient_c + params_.r_th_k_per_w * params_.p_idle_w;
  e_ = 0;
}

double Thermal::energy_max() const {
  const double ic = params_.torque_cont / params_.torque_peak;
  return (1 - ic * ic) * 2.0;
}

void Thermal::step(double i, double ambient_c) {
  const double p = params_.p_idle_w + params_.p_cu_w * i * i;
  const double c_th = params_.tau_th_s / params_.r_th_k_per_w;
  t_ += k_dt * (p - (t_ - ambient_c) / params_.r_th_k_per_w) / c_th;
  const double ic = params_.torque_cont / params_.torque_peak;
  e_ = std::max(0.0, e_ + (i * i - ic * ic) * k_dt);
}

}  // namespace mcemu::core
