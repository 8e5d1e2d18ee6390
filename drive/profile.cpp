#include "drive/profile.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {
namespace {

constexpr double k_time_epsilon = 1e-9;

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

}  // namespace

void Profile::push(double dur, double a) {
  if (!(dur > 0)) return;
  phases_[count_++] = Phase{duration_, p_, v_, a, dur};
  p_ += v_ * dur + 0.5 * a * dur * dur;
  v_ += a * dur;
  duration_ += dur;
  peak_ = std::max(peak_, std::fabs(v_));
}

Profile Profile::hold(double p) {
  Profile pr;
  pr.p_ = pr.p_end_ = p;
  return pr;
}

Profile Profile::stop(double p0, double v0, double decel) {
  Profile pr;
  pr.p_ = p0;
  pr.v_ = v0;
  pr.peak_ = std::fabs(v0);
  if (v0 != 0 && decel > 0) pr.push(std::fabs(v0) / decel, -sign_of(v0) * decel);
  pr.p_end_ = pr.p_;
  pr.v_end_ = 0;
  return pr;
}

Profile Profile::move(double p0, double v0, double target, double vmax, double a, double d, double vf) {
  Profile pr;
  pr.p_ = p0;
  pr.v_ = v0;
  pr.peak_ = std::fabs(v0);
  if (vmax <= 0 || a <= 0 || d <= 0) {
    // a segment that does not move (§7.3): come to rest and stay there without finishing
    if (v0 != 0 && d > 0) pr.push(std::fabs(v0) / d, -sign_of(v0) * d);
    pr.v_ = 0;
    pr.endless_ = true;
    pr.p_end_ = pr.p_;
    return pr;
  }
  vf = std::max(0.0, vf);
  double s = sign_of(target - pr.p_);
  if (s == 0) s = v0 != 0 ? sign_of(v0) : 1.0;
  double dist = std::fabs(target - pr.p_);
  double u0 = s * pr.v_;
  // 1. moving away, or too fast to stop (slow to vf) in time: stop first, then plan from rest
  if (u0 < 0 || (u0 * u0 - vf * vf) / (2 * d) > dist) {
    pr.push(std::fabs(pr.v_) / d, -sign_of(pr.v_) * d);
    pr.v_ = 0;
    const double s_new = sign_of(target - pr.p_);
    if (s_new != 0 && s_new != s) vf = 0;
    if (s_new != 0) s = s_new;
    dist = std::fabs(target - pr.p_);
    u0 = 0;
  }
  // 2. faster than allowed: slow down to vmax first
  if (u0 > vmax) {
    pr.push((u0 - vmax) / d, -s * d);
    pr.v_ = s * vmax;
    u0 = vmax;
    dist = std::fabs(target - pr.p_);
  }
  // 3. the final velocity must be reachable and allowed
  vf = std::min(vf, vmax);
  if (vf > u0 && (vf * vf - u0 * u0) / (2 * a) > dist) vf = std::sqrt(u0 * u0 + 2 * a * dist);
  double vp = std::min(vmax, std::sqrt((2 * a * d * dist + d * u0 * u0 + a * vf * vf) / (a + d)));
  vp = std::max(vp, std::max(u0, vf));
  const double d1 = (vp * vp - u0 * u0) / (2 * a);
  const double d3 = (vp * vp - vf * vf) / (2 * d);
  const double d2 = dist - d1 - d3;
  pr.push((vp - u0) / a, s * a);
  if (d2 > 0 && vp > 0) pr.push(d2 / vp, 0);
  pr.push((vp - vf) / d, -s * d);
  pr.p_end_ = target;
  pr.v_end_ = s * vf;
  return pr;
}

bool Profile::finished(double t) const { return !endless_ && t >= duration_ - k_time_epsilon; }

Kinematics Profile::at(double t) const {
  if (finished(t)) return {p_end_, v_end_, 0};
  for (int i = 0; i < count_; ++i) {
    const Phase& ph = phases_[i];
    if (t < ph.t0 + ph.dur) {
      const double tau = std::max(0.0, t - ph.t0);
      return {ph.p0 + ph.v0 * tau + 0.5 * ph.a * tau * tau, ph.v0 + ph.a * tau, ph.a};
    }
  }
  return {p_, endless_ ? 0.0 : v_, 0};
}

}  // namespace mcemu::core
