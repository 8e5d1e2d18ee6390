#include "drive/modes/homing.hpp"

namespace mcemu::core {
namespace {

constexpr std::uint16_t k_start = 0x0010;
constexpr std::uint16_t k_halt = 0x0100;
constexpr int k_pulse_steps = 10;
constexpr int k_negative_limit = -1;
constexpr int k_positive_limit = -2;

}  // namespace

VelocityCommand Homing::command(double target) const {
  const double a = ctx_.accel_of(ctx_.h.homing_acc);
  return VelocityCommand{target, a, a, a};
}

bool Homing::switch_active() const {
  if (input_ == k_negative_limit) return ctx_.limit_negative;
  if (input_ == k_positive_limit) return ctx_.limit_positive;
  return ctx_.input_level(input_);
}

void Homing::start_block(int dir) {
  phase_ = Phase::block;
  const double v = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.homing_speed_switch)));
  ctx_.gen.start_velocity(command(dir * v));
}

void Homing::enter() {
  phase_ = Phase::none;
  status_ = Status::idle;
  if (ctx_.gen.active()) {
    ctx_.gen.start_stop(ctx_.ramp_decel_6084());
  } else {
    ctx_.gen.reset(ctx_.gen.out().p);
  }
}

void Homing::abort() {
  if (phase_ == Phase::none) return;
  phase_ = Phase::none;
  status_ = Status::idle;
}

void Homing::on_controlword(std::uint16_t cw, std::uint16_t prev) {
  if ((cw & k_halt) && !(prev & k_halt) && phase_ != Phase::none) {
    // halt aborts; releasing it does not resume (§9.1)
    phase_ = Phase::stopping;
    status_ = Status::idle;
    ctx_.gen.start_stop(ctx_.halt_decel());
    return;
  }
  if ((cw & k_start) && !(prev & k_start) && !(cw & k_halt)) start();
}

void Homing::set_reference_here() {
  const std::int64_t home = ctx_.scaling.to_inc(ctx_.num(ctx_.h.home_offset));
  ctx_.home_offset_inc = ctx_.actual_raw_inc - home;
  reference_set_ = true;
}

void Homing::start() {
  method_ = static_cast<std::int8_t>(ctx_.num(ctx_.h.homing_method));
  start_ms_ = ctx_.time_ms;
  status_ = Status::in_progress;
  leg_count_ = 0;
  leg_ = 0;
  const bool rabbit = ctx_.rabbit();
  const bool fh = ctx_.faulhaber();
  const std::int64_t select = ctx_.h.switch_select ? ctx_.num(*ctx_.h.switch_select) : 0;
  const int home_switch = static_cast<int>(select & 0xF);
  const int left_switch = static_cast<int>((select >> 4) & 0xF);
  const int right_switch = static_cast<int>((select >> 8) & 0xF);
  if (rabbit && method_ != 35) {
    fail();
    return;
  }
  switch (method_) {
    case 0:
      phase_ = Phase::pulse;
      pulse_steps_ = 0;
      return;
    case 35:
    case 37:
      set_reference_here();
      ctx_.gen.reset(ctx_.gen.out().p);
      phase_ = Phase::pulse;
      pulse_steps_ = 0;
      return;
    case -18:
    case -19:
      if (fh) {
        fail();
        return;
      }
      start_block(method_ == -18 ? 1 : -1);
      return;
    case -1:
    case -2:
    case -3:
    case -4:
      if (!fh) {
        fail();
        return;
      }
      start_block(method_ == -2 || method_ == -4 ? 1 : -1);
      return;
    case 17:
      input_ = fh ? k_negative_limit : left_switch;
      legs_ = {Leg{-1, true, true}, Leg{+1, false, false}};
      break;
    case 18:
      if (!fh && !ctx_.params.homing.enable_method_18) {
        fail();
        return;
      }
      input_ = fh ? k_positive_limit : right_switch;
      legs_ = {Leg{+1, true, true}, Leg{-1, false, false}};
      break;
    case 19:
      input_ = home_switch;
      legs_ = {Leg{+1, true, true}, Leg{-1, false, false}};
      break;
    case 20:
      input_ = home_switch;
      legs_ = {Leg{-1, true, false}, Leg{+1, false, true}};
      break;
    case 21:
      input_ = home_switch;
      legs_ = {Leg{-1, true, true}, Leg{+1, false, false}};
      break;
    case 22:
      input_ = home_switch;
      legs_ = {Leg{+1, true, false}, Leg{-1, false, true}};
      break;
    default: fail(); return;
  }
  const bool no_switch = (input_ == k_negative_limit && !ctx_.limit_negative_configured) ||
                         (input_ == k_positive_limit && !ctx_.limit_positive_configured);
  if (input_ == 0 || no_switch || (fh && method_ != 17 && method_ != 18)) {
    fail();
    return;
  }
  leg_count_ = 2;
  // the first leg ends when its condition holds; if it already holds, the search starts with leg 2
  leg_ = switch_active() == legs_[0].until_active ? 1 : 0;
  phase_ = Phase::leg;
  start_leg();
}

void Homing::start_leg() {
  const Leg& l = legs_[static_cast<std::size_t>(leg_)];
  const od::Handle speed = l.fast ? ctx_.h.homing_speed_switch : ctx_.h.homing_speed_zero;
  const double v = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(speed)));
  ctx_.gen.start_velocity(command(l.dir * v));
}

void Homing::fail() {
  phase_ = Phase::none;
  status_ = Status::error;
  if (ctx_.gen.active()) ctx_.gen.start_stop(ctx_.halt_decel());
  ctx_.emit(HomingFinished{method_, false});
}

void Homing::succeed() {
  phase_ = Phase::none;
  status_ = Status::attained;
  ctx_.emit(HomingFinished{method_, true});
}

void Homing::generate() {
  Generator& g = ctx_.gen;
  switch (phase_) {
    case Phase::between:
      if (g.out().v == 0) {
        phase_ = Phase::leg;
        start_leg();
      }
      return;
    case Phase::final_stop:
      if (g.out().v == 0) {
        g.reset(static_cast<double>(ctx_.actual_raw_inc));
        reference_set_ = true;
        succeed();
      }
      return;
    case Phase::stopping:
      if (g.finished()) phase_ = Phase::none;
      return;
    default: return;
  }
}

void Homing::monitor() {
  switch (phase_) {
    case Phase::pulse:
      if (++pulse_steps_ >= k_pulse_steps) succeed();
      return;
    case Phase::leg: {
      const Leg& l = legs_[static_cast<std::size_t>(leg_)];
      if (switch_active() == l.until_active) {
        if (leg_ + 1 < leg_count_) {
          ++leg_;
          phase_ = Phase::between;
          ctx_.gen.set_velocity_command(command(0));
        } else {
          set_reference_here();
          reference_set_ = false;  // reported when the axis has stopped
          phase_ = Phase::final_stop;
          ctx_.gen.set_velocity_command(command(0));
        }
        return;
      }
      break;
    }
    default: break;
  }
  if ((phase_ == Phase::leg || phase_ == Phase::block || phase_ == Phase::between) &&
      ctx_.time_ms >= start_ms_ + static_cast<std::uint64_t>(ctx_.params.homing.max_search_ms)) {
    fail();
  }
}

bool Homing::on_block(bool masked) {
  if (phase_ == Phase::block) {
    set_reference_here();
    ctx_.gen.reset(static_cast<double>(ctx_.actual_raw_inc));
    succeed();
    return true;
  }
  if ((phase_ == Phase::leg || phase_ == Phase::between) && masked) {
    fail();
    return true;
  }
  return false;
}

}  // namespace mcemu::core
