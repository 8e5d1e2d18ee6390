#include "drive/generator.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {
namespace {

constexpr double k_dt = 0.001;

}  // namespace

void Generator::filter_reset(double p) {
  taps_.assign(static_cast<std::size_t>(n_j_), p);
  head_ = 0;
  const_run_ = n_j_;
  last_push_ = p;
}

void Generator::filter_push(double p) {
  const_run_ = (p == last_push_) ? const_run_ + 1 : 1;
  last_push_ = p;
  taps_[head_] = p;
  head_ = (head_ + 1) % taps_.size();
}

void Generator::reset(double p, double v) {
  kind_ = Kind::hold;
  profile_ = Profile::hold(p);
  k_ = 0;
  out_ = {p, v, 0};
  trap_ = out_;
  prev_out_v_ = 0;
  profile_done_ = true;
  cmd_ = {};
  filter_reset(p);
}

void Generator::start_move(double target, double vmax, double a, double d, double vf, double jerk_inc_s3) {
  const bool steady = const_run_ >= n_j_ && trap_.v == 0;
  if (scurve_ && kind_ != Kind::move && !steady) {
    // the filter did not track the previous motion: restart it where the demand is, unfiltered
    n_j_ = 1;
    filter_reset(trap_.p);
  }
  profile_ = Profile::move(trap_.p, trap_.v, target, vmax, a, d, vf);
  if (scurve_ && steady) {
    int n = 1;
    if (jerk_inc_s3 > 0 && a > 0) {
      const double by_jerk = std::round(1000.0 * a / jerk_inc_s3);
      const double by_accel = std::round(1000.0 * profile_.peak_speed() / a);
      n = static_cast<int>(std::max(1.0, std::min({by_jerk, by_accel, 100000.0})));
    }
    n_j_ = n;
    filter_reset(trap_.p);
  }
  kind_ = Kind::move;
  move_target_ = target;
  k_ = 0;
  profile_done_ = false;
}

void Generator::start_stop(double decel) {
  profile_ = Profile::stop(out_.p, out_.v, decel);
  kind_ = Kind::stop;
  k_ = 0;
  trap_ = out_;
  // already at rest: the ramp is finished at the instant it is requested
  profile_done_ = profile_.duration() == 0;
  if (profile_done_) {
    out_.a = 0;
    trap_ = out_;
    filter_reset(out_.p);
  }
}

void Generator::start_velocity(const VelocityCommand& cmd) {
  cmd_ = cmd;
  if (kind_ != Kind::velocity) {
    trap_ = out_;
    filter_reset(out_.p);
  }
  kind_ = Kind::velocity;
  profile_done_ = true;
}

bool Generator::active() const {
  if (out_.v != 0) return true;
  switch (kind_) {
    case Kind::hold: return false;
    case Kind::move: return !profile_done_ || const_run_ < n_j_;
    case Kind::stop: return !profile_done_;
    case Kind::velocity: return cmd_.target != 0;
  }
  return false;
}

bool Generator::finished() const {
  switch (kind_) {
    case Kind::hold: return true;
    case Kind::move: return profile_done_ && const_run_ >= n_j_;
    case Kind::stop: return profile_done_;
    case Kind::velocity: return out_.v == 0 && cmd_.target == 0;
  }
  return true;
}

void Generator::tick() {
  switch (kind_) {
    case Kind::hold:
      out_.v = 0;
      out_.a = 0;
      trap_ = out_;
      return;
    case Kind::stop: {
      ++k_;
      const double t = static_cast<double>(k_) * k_dt;
      out_ = profile_.at(t);
      trap_ = out_;
      if (profile_.finished(t)) {
        profile_done_ = true;
        filter_reset(out_.p);
      }
      return;
    }
    case Kind::move: {
      ++k_;
      const double t = static_cast<double>(k_) * k_dt;
      trap_ = profile_.at(t);
      if (profile_.finished(t)) profile_done_ = true;
      if (!scurve_ || n_j_ == 1) {
        if (scurve_) filter_push(trap_.p);
        out_ = trap_;
        return;
      }
      filter_push(trap_.p);
      double p_out = trap_.p;
      if (const_run_ < n_j_) {
        double sum = 0;
        for (double x : taps_) sum += x;
        p_out = sum / static_cast<double>(n_j_);
      }
      const double v = (p_out - out_.p) / k_dt;
      const double a = (v - prev_out_v_) / k_dt;
      prev_out_v_ = v;
      out_ = {p_out, v, a};
      return;
    }
    case Kind::velocity: {
      const double v = out_.v;
      const double vt = cmd_.target;
      double goal = vt;
      double rate = cmd_.decel;
      if ((v > 0 && vt < 0) || (v < 0 && vt > 0)) {
        goal = 0;
        rate = cmd_.reverse;
      } else if (std::fabs(vt) > std::fabs(v)) {
        rate = cmd_.accel;
      }
      const double dv = rate * k_dt;
      double v_new = goal;
      if (std::fabs(goal - v) > dv * (1 + 1e-9)) v_new = v + (goal > v ? dv : -dv);
      out_.p += 0.5 * (v + v_new) * k_dt;
      out_.a = (v_new - v) / k_dt;
      out_.v = v_new;
      prev_out_v_ = v_new;
      trap_ = out_;
      last_push_ = out_.p;
      return;
    }
  }
}

}  // namespace mcemu::core
