// DriveCore: when the next steps would change nothing (quiet_steps) and how to pass over them in
// one call (skip) — "time is asked, not polled" (design.md, spec README "Time").
//
// A step of a drive at rest with the power stage off changes only: drive time, the 2-step supply
// debounce counters while the supply is out of range (the fault is raised already), and the
// winding temperature / I²t energy of the thermal model, which keep relaxing towards their
// equilibrium. Everything else is a fixed point: the plant stands (no torque, the external load
// below the friction), the generator holds at the plant position, no timer of §2.4 runs outside
// Operation Enabled. skip() reproduces exactly those three changes; quiet_steps() ends the quiet
// stretch before the first step in which the thermal model becomes visible (a new rounded
// temperature in 3401h.0A or the model's read hooks, an over-temperature or I²t fault to raise).
#include <algorithm>
#include <cmath>

#include "drive/drive_core.hpp"
#include "drive/faulhaber/fh_faults.hpp"

namespace mcemu::core {
namespace {

// The longest stretch predicted in one call; a longer quiet period is asked again at its end.
constexpr std::uint64_t k_thermal_horizon = 10000;

bool bit_set(std::int64_t mfr, FaultCause cause) { return (mfr >> fault_info(cause).bit) & 1; }

}  // namespace

bool DriveCore::resting() const {
  if (first_step_ || torque_on_ || pending_ != Pending::none || service_move_) return false;
  switch (state_) {
    case PdsState::switch_on_disabled:
    case PdsState::ready_to_switch_on:
    case PdsState::switched_on:
    case PdsState::fault: break;
    default: return false;
  }
  if (static_cast<std::int8_t>(ctx_.num(ctx_.h.mode)) != mode_) return false;  // a mode switch is due
  if (deferred_ != 0 || params_.noise.enabled || pp_.ack()) return false;
  // the plant stands and stays: no velocity, and the external load does not break the friction
  const double pos = plant_.position_inc();
  if (plant_.velocity() != 0 || std::fabs(plant_.external_load()) > params_.coulomb) return false;
  if (prev_position_inc_ != pos || ctx_.actual_velocity_inc_s != 0 || ctx_.actual_raw_inc != round_half_away(pos)) {
    return false;
  }
  if (current_permille_ != 0 || plant_out_.mean_torque != 0 || plant_out_.mean_power != 0 ||
      plant_out_.mean_brake_power != 0 || plant_out_.torque_raw_last != 0 || plant_out_.torque_limit_last != 0) {
    return false;
  }
  const Generator& g = ctx_.gen;
  if (g.kind() != Generator::Kind::hold || g.out().p != pos || g.out().v != 0 || g.out().a != 0) return false;
  if (dc_link_v_ != supply_set_.value_or(params_.supply_nominal_v)) return false;  // regeneration draining
  // step 3 would raise nothing new
  const std::int64_t mfr = this->mfr();
  const double u = supply_voltage();
  if (u < params_.supply_uv_v && !(uv_count_.at_least(2) && bit_set(mfr, FaultCause::under_voltage))) return false;
  if (u > params_.supply_ov_v && !(ov_count_.at_least(2) && bit_set(mfr, FaultCause::over_voltage))) return false;
  if (temperature_c() >= 110 && !bit_set(mfr, FaultCause::over_temperature)) return false;
  if (thermal_.energy() >= thermal_.energy_max() && !bit_set(mfr, FaultCause::i2t)) return false;
  for (const FaultInfo& f : fault_table()) {
    if (f.kind == FaultKind::injected && injected(f.cause) && !((mfr >> f.bit) & 1)) return false;
  }
  const std::int64_t wbit = std::int64_t{1} << fault_info(FaultCause::sensor_warning).bit;
  if (((mfr & wbit) != 0) != injected(FaultCause::sensor_warning)) return false;
  // FAULHABER: the temperature warning follows the rounded temperature, which the thermal
  // prediction below never passes over (a new rounded value ends the quiet stretch)
  if (fh_ && fh_temperature_warning_ != (round_half_away(temperature_c()) >= faulhaber::k_temperature_warning_deg_c)) {
    return false;
  }
  if (state_ == PdsState::switched_on && !(hw_enable_ok() && sw_enable_ok())) return false;
  // step 8 and 10 would write nothing new
  if (compute_inputs() != ctx_.inputs || compose_statusword() != statusword_) return false;
  if (fh_ && fh_device_status() != static_cast<std::uint32_t>(ctx_.num(fh_->device_status))) return false;
  return true;
}

// Steps until the thermal model shows: it is simulated on a copy, with the very operations of
// thermal_step() at zero current, so the prediction is exact.
std::uint64_t DriveCore::thermal_quiet_steps() const {
  Thermal th = thermal_;
  const std::int64_t mfr = this->mfr();
  const bool over_temperature_raised = bit_set(mfr, FaultCause::over_temperature);
  const bool i2t_raised = bit_set(mfr, FaultCause::i2t);
  const bool injected_ot = injected(FaultCause::over_temperature);
  const std::int64_t shown = round_half_away(temperature_c());
  const double i = std::fabs(static_cast<double>(current_permille_)) / 1000.0;
  for (std::uint64_t k = 1; k <= k_thermal_horizon; ++k) {
    const double t0 = th.temperature();
    const double e0 = th.energy();
    th.step(i, ambient_c_);
    if (th.temperature() == t0 && th.energy() == e0) return k_forever;  // a fixed point from here on
    const double t = injected_ot ? 115.0 : th.temperature();
    if (round_half_away(t) != shown) return k - 1;  // step k writes a new temperature
    if (t >= 110 && !over_temperature_raised) return k;
    if (th.energy() >= th.energy_max() && !i2t_raised) return k;
  }
  return k_thermal_horizon;
}

std::uint64_t DriveCore::quiet_steps() const {
  if (!powered_) return k_forever;  // step() does nothing
  if (!settled_ || ctx_.od.generation() != settled_generation_) return 0;
  // The prediction holds until the next full step: skip() follows the predicted trajectory, and
  // every other change unsettles the core first.
  if (!quiet_cache_ || quiet_cache_->first != settle_count_) {
    std::uint64_t until = ctx_.time_ms;
    if (resting()) {
      const std::uint64_t q = thermal_quiet_steps();
      until = q == k_forever ? k_forever : ctx_.time_ms + q;
    }
    quiet_cache_ = std::make_pair(settle_count_, until);
  }
  const std::uint64_t until = quiet_cache_->second;
  if (until == k_forever) return k_forever;
  return until > ctx_.time_ms ? until - ctx_.time_ms : 0;
}

void DriveCore::skip(std::uint64_t n) {
  if (!powered_ || n == 0) return;
  ctx_.time_ms += n;
  const double u = supply_voltage();
  uv_count_.skip(u < params_.supply_uv_v, n);
  ov_count_.skip(u > params_.supply_ov_v, n);
  const double i = std::fabs(static_cast<double>(current_permille_)) / 1000.0;
  for (std::uint64_t k = 0; k < n; ++k) {
    const double t0 = thermal_.temperature();
    const double e0 = thermal_.energy();
    thermal_.step(i, ambient_c_);
    if (thermal_.temperature() == t0 && thermal_.energy() == e0) break;  // constant from here on
  }
}

}  // namespace mcemu::core
