// DriveCore: one simulation step in the normative order of drive-core.md §2.4, mode switching
// (§6) and the monitors of step 8.
#include <cmath>

#include "drive/drive_core.hpp"

namespace mcemu::core {
namespace {

constexpr double k_dt = 0.001;
constexpr int k_following_steps = 20;

}  // namespace

void DriveCore::step() {
  if (!powered_) return;
  ++ctx_.time_ms;      // 1
  check_conditions();  // 2, 3 (supply/ambient are read where used)
  if (!first_step_) check_enable_loss();
  timed_transitions();   // 4
  mode_switch();         // 5
  generate();            // 6
  run_plant();           // 7
  publish_inputs(true);  // 8
  monitors();
  thermal_step();                                                             // 9
  pp_.end_of_step(static_cast<std::uint16_t>(ctx_.num(ctx_.h.controlword)));  // 10
  write_actuals();
  update_statusword();
  first_step_ = false;
  settled_ = true;
  settled_generation_ = ctx_.od.generation();
  ++settle_count_;
}

void DriveCore::leave_mode(std::int8_t mode) {
  if (mode == 1) pp_.clear();
  if (mode == 6) hm_.abort();
  stroke_hold_ = false;
}

void DriveCore::enter_mode(std::int8_t mode) {
  hold_timer_.restart();
  hold_reached_ = false;
  switch (mode) {
    case 1: pp_.enter(); break;
    case 3: pv_.enter(); break;
    case 6: hm_.enter(); break;
    default:
      if (ctx_.gen.active()) {
        ctx_.gen.start_stop(ctx_.ramp_decel_6084());
      } else {
        ctx_.gen.reset(ctx_.gen.out().p);
      }
      break;
  }
}

void DriveCore::mode_switch() { mode_switch_to(static_cast<std::int8_t>(ctx_.num(ctx_.h.mode))); }

void DriveCore::mode_switch_to(std::int8_t requested) {
  if (requested == mode_) return;
  const std::int8_t old = mode_;
  mode_ = requested;
  ctx_.od.set(ctx_.h.mode_display, od::Value{std::int64_t{requested}});
  ctx_.emit(ModeDisplayChanged{requested});
  leave_mode(old);
  if (state_ == PdsState::operation_enabled && pending_ == Pending::none && !service_move_) enter_mode(requested);
}

void DriveCore::generate() {
  demand_prev_ = ctx_.gen.out();
  if (!torque_on_) return;
  if (state_ == PdsState::operation_enabled && pending_ == Pending::none) {
    const auto cw = static_cast<std::uint16_t>(ctx_.num(ctx_.h.controlword));
    if (service_move_) {
      if (ctx_.gen.finished()) {
        service_move_ = false;
        stroke_hold_ = true;
      }
    } else if (!stroke_hold_ || mode_ != 3) {
      switch (mode_) {
        case 1: pp_.generate(cw); break;
        case 3: pv_.generate(cw); break;
        case 6:
          hm_.generate();
          after_homing();
          break;
        default: break;
      }
    }
    if (fh_ && !service_move_) fh_limit_switch_guard();
  }
  ctx_.gen.tick();
}

void DriveCore::run_plant() {
  PlantInput in;
  in.demand0 = demand_prev_;
  in.demand1 = ctx_.gen.out();
  in.torque_on = torque_on_;
  if (fh_) {
    const auto [positive, negative] = torque_on_ ? fh_torque_limits() : std::pair<double, double>{0, 0};
    in.torque_limit = positive;
    in.torque_limit_negative = negative;
  } else {
    in.torque_limit = torque_on_ ? torque_limit() : 0;
  }
  plant_out_ = plant_.step(in);
  const double pos = plant_.position_inc();
  ctx_.actual_raw_inc = round_half_away(pos);
  if (params_.noise.enabled) {
    // §10.8: the reported counter is noisy, and so is the velocity derived from it
    ctx_.actual_raw_inc += next_noise();
    ctx_.actual_velocity_inc_s = static_cast<double>(ctx_.actual_raw_inc - prev_reported_inc_) / k_dt;
  } else {
    ctx_.actual_velocity_inc_s = (pos - prev_position_inc_) / k_dt;
  }
  prev_position_inc_ = pos;
  prev_reported_inc_ = ctx_.actual_raw_inc;
  current_permille_ = torque_on_ ? round_half_away(1000.0 * plant_out_.mean_torque / params_.torque_peak) : 0;
  // without torque the demand follows the actual position (transition 4 starts from there)
  if (!torque_on_) ctx_.gen.reset(pos);
}

int DriveCore::motion_phase() const {
  const double v0 = std::fabs(demand_prev_.v);
  const double v1 = std::fabs(ctx_.gen.out().v);
  const double eps = 1e-9 * std::max(1.0, std::max(v0, v1));
  if (v1 > v0 + eps) return 1;
  if (v1 < v0 - eps) return 2;
  return 0;
}

double DriveCore::torque_limit() const {
  std::int64_t l = std::min<std::int64_t>(ctx_.num(*ctx_.h.max_current), 1000);
  const bool mc349 = preset_.base == model::Base::mc349;
  const bool mcn23 = preset_.base == model::Base::mcn23;
  if (mc349 || mcn23) {
    const bool idle = !ctx_.gen.active();
    const int phase = motion_phase();
    if (idle) {
      l = std::min(l, ctx_.num(*ctx_.h.torque_stall));
    } else if (mc349 && phase == 1) {
      l = std::min(l, ctx_.num(*ctx_.h.torque_acc));
    } else if (mc349 && phase == 2) {
      l = std::min(l, ctx_.num(*ctx_.h.torque_dec));
    }
  }
  return params_.torque_peak * static_cast<double>(std::max<std::int64_t>(l, 0)) / 1000.0;
}

void DriveCore::monitors() {
  const auto& h = ctx_.h;
  if (torque_on_) {
    const bool saturated = std::fabs(plant_out_.torque_raw_last) >= plant_out_.torque_limit_last;
    const double slow = ctx_.scaling.speed_limit_to_inc_s(static_cast<double>(ctx_.num(h.block_speed)));
    block_count_ = (saturated && std::fabs(ctx_.actual_velocity_inc_s) < slow) ? block_count_ + 1 : 0;
    const std::int64_t mask = ctx_.num(h.block_mask);
    // FAULHABER homing on a block (−1…−4) waits 2324h.02 ms (faulhaber.md §7.2)
    const bool fh_block_homing =
        fh_ && state_ == PdsState::operation_enabled && mode_ == 6 && hm_.block_method_running();
    const std::int64_t count_max = fh_block_homing ? ctx_.num(fh_->limit_check_delay) : ctx_.num(h.block_count_max);
    if (block_count_ > count_max) {
      block_count_ = 0;
      const int phase = motion_phase();
      const bool masked = (phase == 1 && (mask & 1)) || (phase == 2 && (mask & 2)) || (phase == 0 && (mask & 4));
      on_block_detected(masked);
    }
    if (params_.following_error_limit_inc > 0 && torque_on_) {
      const std::int64_t err = ctx_.demand_inc() - ctx_.actual_inc();
      following_count_ = std::llabs(err) > params_.following_error_limit_inc ? following_count_ + 1 : 0;
      if (following_count_ > k_following_steps) {
        following_count_ = 0;
        const bool homing_block = state_ == PdsState::operation_enabled && mode_ == 6 && hm_.block_method_running();
        if (!(mask & 8) && !homing_block) stroke_reaction();
      }
    }
  } else {
    block_count_ = 0;
    following_count_ = 0;
  }
  if (state_ != PdsState::operation_enabled || pending_ != Pending::none) return;
  switch (mode_) {
    case 1: pp_.monitor(); break;
    case 3: pv_.monitor(); break;
    case 6:
      hm_.monitor();
      after_homing();
      break;
    default: {
      const std::int64_t window = ctx_.num(h.pos_window);
      bool inside = true;
      if (window < 0x80000000LL) {
        inside = std::llabs(ctx_.demand_inc() - ctx_.actual_inc()) <= ctx_.scaling.distance_to_inc(window);
      }
      hold_reached_ = hold_timer_.update(ctx_.gen.finished() && inside, ctx_.time_ms,
                                         static_cast<std::uint64_t>(ctx_.num(h.pos_window_time)));
      break;
    }
  }
}

void DriveCore::thermal_step() {
  const double i = std::fabs(static_cast<double>(current_permille_)) / 1000.0;
  thermal_.step(i, ambient_c_);
  // §10.11: braking power charges the DC link, the idle load drains it, the supply cannot sink
  const double supply = supply_set_.value_or(params_.supply_nominal_v);
  if (params_.regen.enabled) {
    const double u = std::max(dc_link_v_, 1.0);
    dc_link_v_ = std::max(supply, dc_link_v_ + k_dt * (plant_out_.mean_brake_power - params_.p_idle_w) /
                                                   (params_.regen.capacitance_f * u));
  } else {
    dc_link_v_ = supply;
  }
}

std::int64_t DriveCore::next_noise() {
  // splitmix64 (§10.8): a fixed generator keeps runs identical across standard libraries
  std::uint64_t z = (noise_state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  const auto span = static_cast<std::uint64_t>(2 * params_.noise.inc + 1);
  return static_cast<std::int64_t>(z % span) - params_.noise.inc;
}

}  // namespace mcemu::core
