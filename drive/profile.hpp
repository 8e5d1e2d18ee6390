// Closed-form motion profiles of constant-acceleration phases (drive-core.md §7.6, §4.5).
//
// Contract: a Profile starts at the instant it is planned (t = 0) from a start position and
// velocity; at(t) evaluates it at t seconds. Units are whatever the caller uses consistently
// (the core uses increments, inc/s, inc/s²). A move ends exactly at its target with its final
// velocity; a stop ends at standstill. A move with vmax ≤ 0 never finishes (§7.3: 6081h = 0).
#pragma once

#include <array>

namespace mcemu::core {

struct Kinematics {
  double p = 0;  // position
  double v = 0;  // velocity
  double a = 0;  // acceleration
};

class Profile {
 public:
  // §7.6: time-optimal trapezoid from (p0, v0) to target, arriving with vf ≥ 0 in the travel
  // direction (lowered if unreachable), limited by vmax, accelerating with a and decelerating with d.
  static Profile move(double p0, double v0, double target, double vmax, double a, double d, double vf = 0);
  // §4.5: linear deceleration of v0 to 0 at the rate decel.
  static Profile stop(double p0, double v0, double decel);
  // The state held at p (finished at once).
  static Profile hold(double p);

  Kinematics at(double t) const;
  // t ≥ duration (1 ns tolerance against rounding of the phase times); never for an endless move
  bool finished(double t) const;
  double duration() const { return duration_; }
  double peak_speed() const { return peak_; }
  double end_position() const { return p_end_; }
  double end_velocity() const { return v_end_; }
  bool endless() const { return endless_; }

 private:
  struct Phase {
    double t0;
    double p0;
    double v0;
    double a;
    double dur;
  };
  void push(double dur, double a);

  std::array<Phase, 6> phases_{};
  int count_ = 0;
  double duration_ = 0;
  double p_ = 0;  // running state while planning
  double v_ = 0;
  double p_end_ = 0;
  double v_end_ = 0;
  double peak_ = 0;
  bool endless_ = false;
};

}  // namespace mcemu::core
