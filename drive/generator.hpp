// The demand generator shared by all modes (drive-core.md §7.6, §7.7, §8.2, §4.5): it holds, runs
// a positioning segment, a stop ramp or a velocity ramp, and produces the demand position,
// velocity and acceleration at the end of every 1 ms step.
//
// Contract: positions in increments (raw frame of the plant), velocities inc/s, accelerations
// inc/s². A start_* call plans from the current state at the instant of the call; the first
// evaluation happens at the next tick() (τ = 1 ms). On RABBIT models (scurve = true) positioning
// segments pass through the moving-average filter of §7.7; stop ramps bypass it and leave it at
// standstill; velocity ramps do not use it.
#pragma once

#include <cstdint>
#include <vector>

#include "drive/profile.hpp"

namespace mcemu::core {

// A velocity ramp request (§8.2): rates in inc/s², all > 0.
struct VelocityCommand {
  double target = 0;
  double accel = 1;    // |target| > |v|, same sign
  double decel = 1;    // |target| < |v|, same sign or target 0
  double reverse = 1;  // opposite signs: down to 0 at this rate first
};

class Generator {
 public:
  enum class Kind : std::uint8_t { hold, move, stop, velocity };

  explicit Generator(bool scurve = false) : scurve_(scurve) {}

  // Hold at p (the filter is emptied, steady at p). v ≠ 0 only to hand an actual velocity to the
  // next start_* call (transition 4 with a coasting axis); a plain tick() then holds at p.
  void reset(double p, double v = 0);
  // §7.6/§7.7 segment from the unfiltered state. jerk_inc_s3 ≤ 0 = unlimited (RABBIT only).
  void start_move(double target, double vmax, double a, double d, double vf = 0, double jerk_inc_s3 = 0);
  // §4.5 ramp to standstill from the output state at the rate decel.
  void start_stop(double decel);
  // Velocity ramping from the output state towards cmd (§8.2).
  void start_velocity(const VelocityCommand& cmd);
  void set_velocity_command(const VelocityCommand& cmd) { cmd_ = cmd; }
  // Advance one step (1 ms).
  void tick();

  Kind kind() const { return kind_; }
  const Kinematics& out() const { return out_; }
  // The unfiltered state (start of a re-plan on RABBIT; equal to out() otherwise).
  const Kinematics& trap() const { return trap_; }
  // Trajectory active for statusword bit 8: demand velocity ≠ 0 or a segment not finished.
  bool active() const;
  // The move or stop has ended and the filter is steady; true in hold; velocity: at rest with target 0.
  bool finished() const;
  // The unfiltered move has reached its end state (blending to the next segment may start).
  bool profile_done() const { return profile_done_; }
  // Target of the current move (valid for Kind::move).
  double move_target() const { return move_target_; }
  const Profile& profile() const { return profile_; }
  int filter_length() const { return n_j_; }
  const VelocityCommand& velocity_command() const { return cmd_; }

 private:
  void filter_reset(double p);
  void filter_push(double p);

  bool scurve_;
  Kind kind_ = Kind::hold;
  Profile profile_;
  std::uint64_t k_ = 0;  // steps since planning
  Kinematics out_;
  Kinematics trap_;
  double move_target_ = 0;
  VelocityCommand cmd_;
  bool profile_done_ = true;
  // moving-average filter of §7.7
  std::vector<double> taps_;
  std::size_t head_ = 0;
  int n_j_ = 1;
  int const_run_ = 0;
  double last_push_ = 0;
  double prev_out_v_ = 0;
};

}  // namespace mcemu::core
