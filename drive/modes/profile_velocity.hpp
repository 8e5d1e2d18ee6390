// Profile velocity mode, 6061h = 3 (drive-core.md §8; not on RABBIT models): the generator tracks
// 60FFh with the ramps of §8.2, halt, braking at the soft limits, statusword bits 10, 11 and 12.
//
// Contract: as ProfilePosition — on_controlword() in the 6040h write, generate() at step 6,
// monitor() at step 8, while OE in this mode and no core stop ramp runs. on_run_command() is
// called by the 60FFh hook when the written value changes.
#pragma once

#include <cstdint>

#include "drive/core_context.hpp"
#include "drive/window_timer.hpp"

namespace mcemu::core {

class ProfileVelocity {
 public:
  explicit ProfileVelocity(CoreContext& ctx) : ctx_(ctx) {}

  // Mode entry in OE (also transition 4 in this mode): ramp from the current demand velocity.
  void enter();
  void on_controlword(std::uint16_t cw, std::uint16_t prev);
  void on_run_command();
  void generate(std::uint16_t cw);
  void monitor();

  bool target_reached() const { return reached_; }
  bool speed_zero() const { return zero_; }
  bool internal_limit() const { return pinned_ || ctx_.outside_limits(); }

 private:
  double target_inc_s() const;  // 60FFh converted and clamped to min(607Fh, 6080h)
  VelocityCommand command(double target) const;

  CoreContext& ctx_;
  bool halted_ = false;
  bool reached_ = false;
  bool zero_ = true;
  bool pinned_ = false;
  WindowTimer window_timer_;
  WindowTimer zero_timer_;
  WindowTimer moving_timer_;
};

}  // namespace mcemu::core
