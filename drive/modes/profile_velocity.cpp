#include "drive/modes/profile_velocity.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {
namespace {

constexpr std::uint16_t k_halt = 0x0100;

}  // namespace

double ProfileVelocity::target_inc_s() const {
  const double v = ctx_.scaling.target_velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.target_vel)));
  const double lim = ctx_.speed_limit();
  return std::clamp(v, -lim, lim);
}

VelocityCommand ProfileVelocity::command(double target) const {
  VelocityCommand c;
  c.target = target;
  c.accel = ctx_.profile_accel();
  c.decel = ctx_.ramp_decel_6084();
  c.reverse = ctx_.quick_stop_decel();
  return c;
}

void ProfileVelocity::enter() {
  halted_ = false;
  pinned_ = false;
  reached_ = false;
  window_timer_.restart();
  zero_timer_.restart();
  moving_timer_.restart();
  const double thr = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.vel_threshold)));
  zero_ = std::fabs(ctx_.actual_velocity_inc_s) <= thr;
  ctx_.gen.start_velocity(command(target_inc_s()));
}

void ProfileVelocity::on_controlword(std::uint16_t cw, std::uint16_t prev) {
  if (((cw ^ prev) & k_halt) == 0) return;
  halted_ = (cw & k_halt) != 0;
  reached_ = false;
  window_timer_.restart();
}

void ProfileVelocity::on_run_command() {
  reached_ = false;
  window_timer_.restart();
}

void ProfileVelocity::generate(std::uint16_t cw) {
  halted_ = (cw & k_halt) != 0;
  Generator& g = ctx_.gen;
  if (halted_) {
    pinned_ = false;
    VelocityCommand c = command(0);
    c.decel = c.reverse = ctx_.halt_decel();
    if (g.kind() != Generator::Kind::velocity) {
      g.start_velocity(c);
    } else {
      g.set_velocity_command(c);
    }
    return;
  }
  const double vt = target_inc_s();
  const auto lim = ctx_.limits_raw();
  const double p = g.out().p;
  const double v = g.out().v;
  if (lim && g.kind() == Generator::Kind::move) {
    // braking towards a limit: keep going while the target still points at it
    const bool at_max = g.move_target() == static_cast<double>(lim->second);
    const bool towards = at_max ? vt > 0 : vt < 0;
    if (towards) {
      pinned_ = g.finished();
      return;
    }
    pinned_ = false;
    g.start_velocity(command(vt));
    return;
  }
  pinned_ = false;
  if (g.kind() != Generator::Kind::velocity) {
    g.start_velocity(command(vt));
  } else {
    g.set_velocity_command(command(vt));
  }
  if (!lim || v == 0) return;
  const double d = ctx_.ramp_decel_6084();
  const double limit = v > 0 ? static_cast<double>(lim->second) : static_cast<double>(lim->first);
  const double remaining = v > 0 ? limit - p : p - limit;
  const bool towards = v > 0 ? vt > 0 : vt < 0;
  if (!towards) return;
  // next step's travel included so the demand never passes the limit
  if (remaining <= v * v / (2 * d) + std::fabs(v) * 0.001) {
    const double d_req = remaining > 0 ? std::max(d, v * v / (2 * remaining)) : d;
    g.start_move(limit, std::fabs(v), ctx_.profile_accel(), d_req);
  }
}

void ProfileVelocity::monitor() {
  const double va = ctx_.actual_velocity_inc_s;
  const Generator& g = ctx_.gen;
  if (halted_) {
    reached_ = g.out().v == 0;
  } else {
    const double vt = target_inc_s();
    const double window = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.vel_window)));
    reached_ = window_timer_.update(std::fabs(va - vt) <= window, ctx_.time_ms,
                                    static_cast<std::uint64_t>(ctx_.num(ctx_.h.vel_window_time)));
  }
  const double thr = ctx_.scaling.velocity_to_inc_s(static_cast<double>(ctx_.num(ctx_.h.vel_threshold)));
  const auto hold = static_cast<std::uint64_t>(ctx_.num(ctx_.h.vel_threshold_time));
  const bool below = std::fabs(va) <= thr;
  const bool went_zero = zero_timer_.update(below, ctx_.time_ms, hold);
  const bool went_moving = moving_timer_.update(!below, ctx_.time_ms, hold);
  if (!zero_ && went_zero) zero_ = true;
  if (zero_ && went_moving) zero_ = false;
}

}  // namespace mcemu::core
