#include "drive/modes/profile_position.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {
namespace {

constexpr std::uint16_t k_new_setpoint = 0x0010;
constexpr std::uint16_t k_immediate = 0x0020;
constexpr std::uint16_t k_relative = 0x0040;
constexpr std::uint16_t k_halt = 0x0100;
constexpr std::uint16_t k_change_on_setpoint = 0x0200;
constexpr std::uint64_t k_ack_hold_ms = 100;

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

}  // namespace

void ProfilePosition::reset_reference() { reference_user_ = ctx_.user_of(ctx_.actual_inc()); }

void ProfilePosition::enter() {
  clear();
  reset_reference();
  reached_ = false;
  reached_timer_.restart();
  if (ctx_.gen.active()) {
    ctx_.gen.start_stop(ctx_.ramp_decel_6084());
  } else {
    ctx_.gen.reset(ctx_.gen.out().p);  // e.g. a velocity generator at rest: hold there
  }
}

void ProfilePosition::clear() {
  active_.reset();
  buffer_.clear();
  ack_ = false;
  halted_ = false;
  limit_ = false;
}

void ProfilePosition::interrupt() {
  std::optional<Setpoint> running;
  if (active_ && !ctx_.gen.finished()) running = active_;
  clear();
  interrupted_ = running;
}

bool ProfilePosition::resume() {
  if (!interrupted_) return false;
  active_ = interrupted_;
  interrupted_.reset();
  buffer_.clear();
  halted_ = false;
  reached_ = false;
  reached_timer_.restart();
  plan(*active_, nullptr);
  return true;
}

double ProfilePosition::vmax_of(const Setpoint& sp) const { return std::min(sp.velocity, ctx_.speed_limit()); }

bool ProfilePosition::idle() const {
  return buffer_.empty() && ctx_.gen.finished() && ctx_.gen.kind() != Generator::Kind::velocity;
}

ProfilePosition::Setpoint ProfilePosition::build(std::uint16_t cw, bool starts_now) const {
  Setpoint sp;
  sp.velocity = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.profile_vel)));
  sp.relative = (cw & k_relative) != 0;
  sp.blend = (cw & k_change_on_setpoint) != 0;
  const std::int64_t target = ctx_.num(ctx_.h.target_pos);
  const std::int64_t option = ctx_.num(ctx_.h.pos_option);
  const bool rotary = (option & 0xC0) != 0;
  const SoftLimits lim = ctx_.soft_limits();
  std::int64_t t = target;
  if (sp.relative) {
    std::int64_t base = reference_user_;
    if ((option & 0x3) == 1) base = ctx_.user_of(ctx_.demand_inc());
    if ((option & 0x3) == 2) base = ctx_.user_of(ctx_.actual_inc());
    t = base + target;
  } else if (rotary) {
    const std::int64_t low = lim.on ? lim.min_user : 0;
    const std::int64_t range = lim.on ? lim.max_user - lim.min_user : ctx_.scaling.revolution_user();
    std::int64_t pu = ctx_.user_of(ctx_.demand_inc());
    if (!starts_now) {
      if (!buffer_.empty()) {
        pu = buffer_.back().target_user;
      } else if (active_) {
        pu = active_->target_user;
      }
    }
    const std::int64_t pw = low + floor_mod(pu - low, range);
    const std::int64_t tw = low + floor_mod(target - low, range);
    std::int64_t delta = 0;
    switch (option & 0xC0) {
      case 0x40: delta = -floor_mod(pw - tw, range); break;
      case 0x80: delta = floor_mod(tw - pw, range); break;
      default:
        delta = floor_mod(tw - pw, range);
        if (2 * delta > range) delta -= range;
        break;
    }
    t = pu + delta;
  }
  if (!rotary && lim.on) {
    const std::int64_t c = std::clamp(t, lim.min_user, lim.max_user);
    sp.clamped = c != t;
    t = c;
  }
  sp.target_user = t;
  sp.target_raw = ctx_.raw_of(ctx_.scaling.to_inc(t));
  return sp;
}

double ProfilePosition::end_velocity(const Setpoint& sp, const Setpoint* next) const {
  if (next == nullptr || !next->blend) return 0;
  const Kinematics& k = ctx_.gen.trap();
  double dir = sign_of(static_cast<double>(sp.target_raw) - k.p);
  if (dir == 0) dir = sign_of(k.v);
  const double dir_next = sign_of(static_cast<double>(next->target_raw - sp.target_raw));
  if (dir == 0 || dir != dir_next) return 0;
  const double dist_next = std::fabs(static_cast<double>(next->target_raw - sp.target_raw));
  return std::min({vmax_of(sp), vmax_of(*next), std::sqrt(2 * ctx_.profile_decel() * dist_next)});
}

void ProfilePosition::plan(const Setpoint& sp, const Setpoint* next) {
  ctx_.gen.start_move(static_cast<double>(sp.target_raw), vmax_of(sp), ctx_.profile_accel(), ctx_.profile_decel(),
                      end_velocity(sp, next), ctx_.rabbit() ? ctx_.jerk() : 0);
}

void ProfilePosition::accept(std::uint16_t cw) {
  const bool immediate = (cw & k_immediate) != 0;
  const bool starts_now = !halted_ && (immediate || idle());
  const Setpoint sp = build(cw, starts_now);
  interrupted_.reset();
  reference_user_ = sp.target_user;
  last_target_inc_ = sp.target_raw - ctx_.home_offset_inc;
  ack_ = true;
  ack_time_ = ctx_.time_ms;
  reached_ = false;
  reached_timer_.restart();
  bool buffered = false;
  if (immediate) {
    buffer_.clear();
    active_ = sp;
    if (!halted_) plan(sp, nullptr);
  } else if (starts_now) {
    active_ = sp;
    plan(sp, nullptr);
  } else if (halted_ && !active_) {
    active_ = sp;
  } else {
    buffer_.push_back(sp);
    buffered = true;
    if (sp.blend && buffer_.size() == 1 && active_ && !halted_ && ctx_.gen.kind() == Generator::Kind::move &&
        !ctx_.gen.profile_done()) {
      plan(*active_, &buffer_.front());
    }
  }
  ctx_.emit(SetpointAccepted{sp.target_raw - ctx_.home_offset_inc, buffered});
  if (sp.clamped) ctx_.emit(Diagnostic{DiagnosticLevel::info, "target clamped to the software position limit"});
}

void ProfilePosition::start_halt() {
  halted_ = true;
  reached_ = false;
  reached_timer_.restart();
  ctx_.gen.start_stop(ctx_.halt_decel());
}

void ProfilePosition::release_halt() {
  halted_ = false;
  reached_ = false;
  reached_timer_.restart();
  if (active_) plan(*active_, buffer_.empty() ? nullptr : &buffer_.front());
}

void ProfilePosition::on_controlword(std::uint16_t cw, std::uint16_t prev) {
  const bool halt = (cw & k_halt) != 0;
  if (halt && !halted_) {
    start_halt();
  } else if (!halt && halted_) {
    release_halt();
  }
  if ((cw & k_new_setpoint) && !(prev & k_new_setpoint)) {
    if (ack_) {
      ctx_.emit(SetpointRejected{SetpointRejectReason::buffer_full});
      ctx_.emit(Diagnostic{DiagnosticLevel::info, "set-point ignored: buffer full"});
    } else {
      accept(cw);
    }
  }
  if (!(cw & k_new_setpoint) && ack_ && buffer_.size() < k_buffer_size) ack_ = false;
}

void ProfilePosition::on_limits_changed(const SoftLimits& lim) {
  if (ctx_.rotary_operation() || !lim.on) return;
  const auto clamp_sp = [&](Setpoint& sp) {
    const std::int64_t c = std::clamp(sp.target_user, lim.min_user, lim.max_user);
    if (c == sp.target_user) return false;
    sp.target_user = c;
    sp.target_raw = ctx_.raw_of(ctx_.scaling.to_inc(c));
    sp.clamped = true;
    return true;
  };
  for (auto& sp : buffer_) clamp_sp(sp);
  if (!active_) return;
  const bool running = ctx_.gen.kind() == Generator::Kind::move && !ctx_.gen.profile_done();
  if (clamp_sp(*active_)) {
    limit_ = true;
    if (running && !halted_) plan(*active_, buffer_.empty() ? nullptr : &buffer_.front());
  }
}

void ProfilePosition::generate(std::uint16_t cw) {
  const bool halt = (cw & k_halt) != 0;
  if (halt && !halted_) {
    start_halt();
  } else if (!halt && halted_) {
    release_halt();
  }
  if (halted_ || buffer_.empty()) return;
  const Generator& g = ctx_.gen;
  const bool blend = buffer_.front().blend && g.kind() == Generator::Kind::move;
  const bool done = blend ? g.profile_done() : (g.finished() && g.kind() != Generator::Kind::velocity);
  if (!done) return;
  active_ = buffer_.front();
  buffer_.pop_front();
  plan(*active_, buffer_.empty() ? nullptr : &buffer_.front());
}

void ProfilePosition::monitor() {
  if (halted_) {
    reached_ = ctx_.gen.finished();
  } else {
    const std::int64_t window = ctx_.num(ctx_.h.pos_window);
    bool inside = true;
    if (window < 0x80000000LL) {
      const std::int64_t err = ctx_.demand_inc() - ctx_.actual_inc();
      inside = (err < 0 ? -err : err) <= ctx_.scaling.distance_to_inc(window);
    }
    reached_ = reached_timer_.update(idle() && inside, ctx_.time_ms,
                                     static_cast<std::uint64_t>(ctx_.num(ctx_.h.pos_window_time)));
  }
  limit_ = (active_ && active_->clamped) || ctx_.outside_limits();
}

void ProfilePosition::end_of_step(std::uint16_t cw) {
  if (ack_ && buffer_.size() < k_buffer_size && (!(cw & k_new_setpoint) || ctx_.time_ms >= ack_time_ + k_ack_hold_ms)) {
    ack_ = false;
  }
}

}  // namespace mcemu::core
