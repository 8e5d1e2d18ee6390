// DriveCore: the CiA 402 power drive system (§4), enable checks (§4.6) and faults (§11).
#include <algorithm>
#include <cmath>

#include "drive/drive_core.hpp"

namespace mcemu::core {
namespace {

constexpr std::uint16_t k_fault_reset = 0x0080;

od::Value num(std::int64_t v) { return od::Value{v}; }

}  // namespace

od::AbortCode DriveCore::on_controlword(std::uint16_t cw, std::uint16_t prev) {
  if (!powered_) return od::AbortCode::none;
  if ((cw & k_fault_reset) && !(prev & k_fault_reset) && state_ == PdsState::fault) {
    try_fault_reset();
  } else if (!(cw & k_fault_reset)) {
    apply_state_command(cw);
  }
  if (state_ == PdsState::operation_enabled && pending_ == Pending::none && !service_move_) {
    switch (mode_) {
      case 1: pp_.on_controlword(cw, prev); break;
      case 3: pv_.on_controlword(cw, prev); break;
      case 6:
        hm_.on_controlword(cw, prev);
        after_homing();
        break;
      default: break;
    }
  }
  update_statusword();
  return od::AbortCode::none;
}

void DriveCore::apply_state_command(std::uint16_t cw) {
  const bool shutdown = (cw & 0x0087) == 0x0006;
  const bool switch_on = (cw & 0x008F) == 0x0007;
  const bool enable = (cw & 0x008F) == 0x000F;
  const bool disable_voltage = (cw & 0x0082) == 0x0000;
  const bool quick = (cw & 0x0086) == 0x0002;
  const auto& h = ctx_.h;
  switch (state_) {
    case PdsState::switch_on_disabled:
      if (shutdown) set_state(PdsState::ready_to_switch_on, 2);
      return;
    case PdsState::ready_to_switch_on:
      if (switch_on || enable) {
        if (!switch_on_allowed()) return;
        if (switch_on) {
          set_state(PdsState::switched_on, 3);
        } else {
          enter_operation_enabled(4);
        }
      } else if (disable_voltage || quick) {
        set_state(PdsState::switch_on_disabled, 7);
      }
      return;
    case PdsState::switched_on:
      if (enable) {
        enter_operation_enabled(4);
      } else if (shutdown) {
        set_state(PdsState::ready_to_switch_on, 6);
      } else if (disable_voltage || quick) {
        set_state(PdsState::switch_on_disabled, 10);
      }
      return;
    case PdsState::operation_enabled:
      if (disable_voltage) {
        leave_operation_enabled();
        set_state(PdsState::switch_on_disabled, 9);
        return;
      }
      if (quick) {
        quick_stop();
        return;
      }
      if (pending_ == Pending::to_switched_on || pending_ == Pending::to_ready) {
        if (enable) {
          // the pending 5/8 is cancelled; the ramp ends at standstill and the axis stays OE
          pending_ = Pending::none;
        } else if (shutdown) {
          pending_ = Pending::to_ready;
          pending_transition_ = 8;
        } else if (switch_on) {
          pending_ = Pending::to_switched_on;
          pending_transition_ = 5;
        }
        return;
      }
      if (pending_ != Pending::none) return;
      if (switch_on || shutdown) {
        const int transition = switch_on ? 5 : 8;
        const PdsState target = switch_on ? PdsState::switched_on : PdsState::ready_to_switch_on;
        const std::int64_t option = ctx_.num(switch_on ? h.disable_option : h.shutdown_option);
        leave_operation_enabled();
        if (option == 0) {
          set_state(target, transition);
        } else {
          begin_stop(switch_on ? Pending::to_switched_on : Pending::to_ready, ctx_.ramp_decel_6084());
          pending_transition_ = transition;
        }
      }
      return;
    case PdsState::quick_stop_active:
      if (disable_voltage) {
        pending_ = Pending::none;
        set_state(PdsState::switch_on_disabled, 12);
      } else if (enable && (quick_stop_option_ == 5 || quick_stop_option_ == 6)) {
        enter_operation_enabled(16);
      }
      return;
    case PdsState::not_ready_to_switch_on:
    case PdsState::fault_reaction_active:
    case PdsState::fault: return;
  }
}

void DriveCore::set_state(PdsState to, int transition) {
  const PdsState from = state_;
  state_ = to;
  switch (to) {
    case PdsState::operation_enabled:
    case PdsState::quick_stop_active: set_torque(true); break;
    case PdsState::fault_reaction_active: break;
    default:
      set_torque(false);
      pending_ = Pending::none;
      break;
  }
  ctx_.emit(StateChanged{from, to, transition});
}

void DriveCore::set_torque(bool on) {
  if (on == torque_on_) return;
  torque_on_ = on;
  if (!on) {
    ctx_.gen.reset(plant_.position_inc());
    plant_.clear_integrator();
  }
  ctx_.emit(PowerStage{on});
}

void DriveCore::enter_operation_enabled(int transition) {
  const PdsState from = state_;
  service_move_ = false;
  stroke_hold_ = false;
  if (transition == 16) {
    state_ = PdsState::operation_enabled;
    ctx_.emit(StateChanged{from, state_, 16});
    if (mode_ == 3) pv_.enter();
    if (mode_ == 6) hm_.enter();
    hold_timer_.restart();
    return;
  }
  // transition 4 (also 3+4): demand := actual position and velocity, integrator cleared
  ctx_.gen.reset(plant_.position_inc(), plant_.velocity_inc_s());
  plant_.clear_integrator();
  state_ = PdsState::operation_enabled;
  set_torque(true);
  pp_.reset_reference();
  hold_timer_.restart();
  hold_reached_ = false;
  switch (mode_) {
    case 1: pp_.enter(); break;
    case 3: pv_.enter(); break;
    case 6: hm_.enter(); break;
    default:
      if (ctx_.gen.active()) ctx_.gen.start_stop(ctx_.ramp_decel_6084());
      break;
  }
  ctx_.emit(StateChanged{from, state_, 4});
}

void DriveCore::leave_operation_enabled() {
  pp_.clear();
  hm_.abort();
  service_move_ = false;
  stroke_hold_ = false;
}

void DriveCore::begin_stop(Pending pending, double decel) {
  pending_ = pending;
  ctx_.gen.start_stop(decel);
}

void DriveCore::quick_stop() {
  pp_.interrupt();
  hm_.abort();
  service_move_ = false;
  stroke_hold_ = false;
  pending_ = Pending::none;
  quick_stop_option_ = static_cast<int>(ctx_.num(ctx_.h.quick_stop_option));
  set_state(PdsState::quick_stop_active, 11);
  switch (quick_stop_option_) {
    case 0: set_state(PdsState::switch_on_disabled, 12); return;
    case 2:
      begin_stop(Pending::to_disabled, ctx_.quick_stop_decel());
      pending_transition_ = 12;
      return;
    case 5: ctx_.gen.start_stop(ctx_.ramp_decel_6084()); return;
    case 6: ctx_.gen.start_stop(ctx_.quick_stop_decel()); return;
    default:
      begin_stop(Pending::to_disabled, ctx_.ramp_decel_6084());
      pending_transition_ = 12;
      return;
  }
}

void DriveCore::finish_pending() {
  const Pending p = pending_;
  pending_ = Pending::none;
  switch (p) {
    case Pending::to_switched_on: set_state(PdsState::switched_on, pending_transition_); return;
    case Pending::to_ready: set_state(PdsState::ready_to_switch_on, pending_transition_); return;
    case Pending::to_disabled: set_state(PdsState::switch_on_disabled, pending_transition_); return;
    case Pending::to_fault: set_state(PdsState::fault, 14); return;
    case Pending::none: return;
  }
}

void DriveCore::timed_transitions() {
  if (state_ == PdsState::not_ready_to_switch_on) {
    set_state(PdsState::switch_on_disabled, 1);
    return;
  }
  if (pending_ != Pending::none && ctx_.gen.finished()) finish_pending();
}

// ---- enable checks (§4.6)

// A 9 in the high byte requires the input high, else a 9 in the low byte requires it low
// (iofunc.md §4.11); all such inputs must agree.
bool DriveCore::sw_enable_ok() const {
  const EnableMasks& m = enable_masks_.get(ctx_.od, [this] {
    EnableMasks masks;
    for (int i = 0; i < 10; ++i) {
      const std::int64_t f = ctx_.num(ctx_.h.input_function[static_cast<std::size_t>(i)]);
      const std::uint32_t bit = 1u << (16 + i);  // input i + 1 (CoreContext::input_level)
      if (((f >> 8) & 0xFF) == 9) {
        masks.high |= bit;
      } else if ((f & 0xFF) == 9) {
        masks.low |= bit;
      }
    }
    return masks;
  });
  return (ctx_.inputs & m.high) == m.high && (ctx_.inputs & m.low) == 0;
}

bool DriveCore::hw_enable_ok() const { return !params_.hw_enable_fitted || ctx_.input_level(params_.hw_enable_input); }

bool DriveCore::switch_on_allowed() {
  if (hw_enable_ok() && sw_enable_ok()) return true;
  raise(FaultCause::hw_sw_enable);
  return false;
}

void DriveCore::check_enable_loss() {
  const bool powered_states =
      state_ == PdsState::switched_on || state_ == PdsState::operation_enabled || state_ == PdsState::quick_stop_active;
  if (!powered_states) return;
  if (!hw_enable_ok()) {
    raise(FaultCause::hw_sw_enable);
    return;
  }
  if (sw_enable_ok()) return;
  // Software Enable lost: stop per 605Ch and go to SOD without a fault (§4.6)
  if (state_ == PdsState::switched_on) {
    set_state(PdsState::switch_on_disabled, 10);
  } else if (state_ == PdsState::quick_stop_active) {
    set_state(PdsState::switch_on_disabled, 12);
  } else if (pending_ != Pending::to_disabled) {
    leave_operation_enabled();
    if (ctx_.num(ctx_.h.disable_option) == 0) {
      set_state(PdsState::switch_on_disabled, 9);
    } else {
      begin_stop(Pending::to_disabled, ctx_.ramp_decel_6084());
      pending_transition_ = 9;
    }
  }
}

// ---- faults (§11)

void DriveCore::record_history(std::uint16_t code) {
  auto& od = ctx_.od;
  const auto& h = ctx_.h.history;
  for (std::size_t s = 4; s >= 2; --s) od.set(h[s], num(od.number(h[s - 1])));
  od.set(h[1], num(code));
  od.set(h[0], num(std::min<std::int64_t>(od.number(h[0]) + 1, 4)));
}

void DriveCore::raise(FaultCause cause) {
  const FaultInfo& info = fault_info(cause);
  if (info.kind == FaultKind::warning) return;
  auto& od = ctx_.od;
  const std::int64_t bit = std::int64_t{1} << info.bit;
  const std::int64_t mfr = this->mfr();
  if (mfr & bit) return;
  const std::int64_t next = mfr | bit;
  if (fh_) {
    fh_raise(cause, next);
  } else {
    set_mfr(next);
    od.set(ctx_.h.error_register, num(error_register(static_cast<std::uint32_t>(next))));
    od.set(ctx_.h.error_code, num(info.code));
    record_history(info.code);
    ctx_.emit(FaultRaised{cause, info.code});
    ctx_.emit(Emcy{info.code, info.reg, {}});
  }
  if (state_ == PdsState::fault || state_ == PdsState::not_ready_to_switch_on) return;
  if (state_ == PdsState::fault_reaction_active) {
    if (info.torque_off) set_state(PdsState::fault, 14);
    return;
  }
  enter_fault_reaction(info.torque_off);
}

void DriveCore::enter_fault_reaction(bool torque_off) {
  const bool torque_applied = torque_on_;
  leave_operation_enabled();
  pending_ = Pending::none;
  set_state(PdsState::fault_reaction_active, 13);
  const std::int64_t option = ctx_.num(ctx_.h.fault_option);
  if (torque_off || !torque_applied || option == 0) {
    set_state(PdsState::fault, 14);
    return;
  }
  begin_stop(Pending::to_fault, option == 1 ? ctx_.ramp_decel_6084() : ctx_.quick_stop_decel());
}

bool DriveCore::reset_allowed(FaultCause cause) const {
  switch (cause) {
    case FaultCause::over_voltage: return supply_voltage() <= params_.supply_ov_v - 2;
    case FaultCause::under_voltage: return supply_voltage() >= params_.supply_uv_v + 1;
    case FaultCause::over_temperature: return temperature_c() <= 100;
    case FaultCause::i2t: return thermal_.energy() <= thermal_.energy_max() / 2;
    case FaultCause::needs_reset: return false;
    default: break;
  }
  const FaultInfo& info = fault_info(cause);
  if (info.kind == FaultKind::event || info.kind == FaultKind::warning) return true;
  return !injected(cause);
}

void DriveCore::try_fault_reset() {
  const std::int64_t mfr = this->mfr();
  std::vector<FaultCause> blocking;
  for (const FaultInfo& f : fault_table()) {
    if (f.kind == FaultKind::warning) continue;
    bool present = (mfr >> f.bit) & 1;
    if (f.kind == FaultKind::injected) present = present || injected(f.cause);
    if (f.cause == FaultCause::under_voltage) present = present || supply_voltage() < params_.supply_uv_v;
    if (f.cause == FaultCause::over_voltage) present = present || supply_voltage() > params_.supply_ov_v;
    if (f.cause == FaultCause::over_temperature) present = present || temperature_c() >= 110;
    if (f.cause == FaultCause::i2t) present = present || thermal_.energy() >= thermal_.energy_max();
    if (present && !reset_allowed(f.cause)) blocking.push_back(f.cause);
  }
  if (!blocking.empty()) {
    ctx_.emit(FaultResetRefused{std::move(blocking)});
    return;
  }
  const std::int64_t kept = mfr & ~static_cast<std::int64_t>(k_error_bits_mask);
  set_mfr(kept);
  if (fh_) {
    fh_fault_reset_done(kept);
    return;
  }
  ctx_.od.set(ctx_.h.error_register, num(0));
  set_state(PdsState::switch_on_disabled, 15);
  ctx_.emit(FaultResetDone{});
  ctx_.emit(Emcy{0x0000, 0x00, {}});
}

void DriveCore::check_conditions() {
  const double u = supply_voltage();
  uv_count_.step(u < params_.supply_uv_v);
  ov_count_.step(u > params_.supply_ov_v);
  if (first_step_) return;
  if (uv_count_.at_least(2)) raise(FaultCause::under_voltage);
  if (ov_count_.at_least(2)) raise(FaultCause::over_voltage);
  if (temperature_c() >= 110) raise(FaultCause::over_temperature);
  if (thermal_.energy() >= thermal_.energy_max()) raise(FaultCause::i2t);
  for (const FaultInfo& f : fault_table()) {
    const std::uint32_t bit = 1u << static_cast<int>(f.cause);
    if (f.kind == FaultKind::injected && (injected_ & bit)) raise(f.cause);
    if (f.kind == FaultKind::event && (deferred_ & bit)) {
      deferred_ &= ~bit;
      raise(f.cause);
    }
  }
  // warnings follow their condition
  const std::int64_t mfr = this->mfr();
  const FaultInfo& w = fault_info(FaultCause::sensor_warning);
  const std::int64_t wbit = std::int64_t{1} << w.bit;
  const std::int64_t next = injected(FaultCause::sensor_warning) ? (mfr | wbit) : (mfr & ~wbit);
  if (next != mfr) set_mfr(next);
  if (fh_) fh_check_temperature_warning();
}

// ---- block / following error (§10.6)

void DriveCore::on_block_detected(bool masked) {
  if (state_ == PdsState::operation_enabled && mode_ == 6 && hm_.running() && pending_ == Pending::none) {
    if (hm_.on_block(masked)) {
      after_homing();
      return;
    }
  }
  if (masked) return;
  stroke_reaction();
}

void DriveCore::stroke_reaction() {
  const std::int64_t option = ctx_.num(ctx_.h.stroke_option);
  if (option < 1 || option > 3) {
    raise(FaultCause::stroke);
    return;
  }
  // stroke option 1–3: EMCY only, not recorded (§10.6, §11.4)
  ctx_.emit(Emcy{0x7121, static_cast<std::uint8_t>(ctx_.od.number(ctx_.h.error_register)), {}});
  if (state_ != PdsState::operation_enabled || pending_ != Pending::none) return;
  pp_.clear();
  hm_.abort();
  // the motion is aborted where the axis is: the demand that ran ahead of the blocked axis is
  // dropped, so the axis does not keep pushing
  ctx_.gen.reset(plant_.position_inc(), plant_.velocity_inc_s());
  plant_.clear_integrator();
  if (option == 1) {
    ctx_.gen.start_stop(ctx_.quick_stop_decel());
    stroke_hold_ = true;
    service_move_ = false;
    return;
  }
  const std::int64_t pos = ctx_.num(ctx_.h.stroke_position);
  const double target =
      option == 2 ? static_cast<double>(ctx_.raw_of(pos)) : static_cast<double>(ctx_.actual_raw_inc + pos);
  const double v = ctx_.scaling.speed_limit_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.stroke_velocity)));
  ctx_.gen.start_move(target, v, ctx_.profile_accel(), ctx_.profile_decel());
  service_move_ = true;
}

void DriveCore::after_homing() {
  if (!hm_.take_reference_set()) return;
  pp_.reset_reference();
  plant_.clear_integrator();
  write_actuals();  // the position changes inside the call that found the reference (§9.3)
}

}  // namespace mcemu::core
