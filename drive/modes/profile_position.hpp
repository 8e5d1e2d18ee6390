// Profile position mode, 6061h = 1 (drive-core.md §7): set-point handshake, single set-point /
// set of set-points (buffer of 20) / change on set-point, relative targets with the 60F2h
// reference, rotary targets, soft-limit clamping, halt, and statusword bits 10, 11, 12.
//
// Contract: the core calls on_controlword() inside the 6040h write while OE in this mode, generate()
// at step 6 and monitor() at step 8 while OE in this mode and no core stop ramp runs, end_of_step()
// at step 10. Targets are planned in raw increments on the shared generator. The relative
// reference lives here in unwrapped user units (§7.4).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "drive/core_context.hpp"
#include "drive/window_timer.hpp"

namespace mcemu::core {

class ProfilePosition {
 public:
  static constexpr std::size_t k_buffer_size = 20;

  explicit ProfilePosition(CoreContext& ctx) : ctx_(ctx) {}

  // Mode entry in OE (also transition 4 in this mode): reference := actual, decelerate with 6084h
  // if the demand still moves, held position counts as the target.
  void enter();
  // Leaving the mode or OE, quick stop, fault: buffer and running set-point dropped, bit 12 cleared.
  void clear();
  // Transition 11: remember the running set-point for resume_interrupted_motion(), then clear().
  void interrupt();
  // Re-plan an interrupted set-point from standstill (CM / ContinueMotion); false if none.
  bool resume();

  void on_controlword(std::uint16_t cw, std::uint16_t prev);
  // 607Dh written (the new limits, before they are stored): clamp targets, re-plan a running one.
  void on_limits_changed(const SoftLimits& lim);
  void generate(std::uint16_t cw);
  void monitor();
  void end_of_step(std::uint16_t cw);

  bool ack() const { return ack_; }
  bool target_reached() const { return reached_; }
  bool internal_limit() const { return limit_; }
  std::size_t buffered() const { return buffer_.size(); }

  // relative reference (§7.4)
  void reset_reference();  // := user(actual)
  std::int64_t reference_user() const { return reference_user_; }
  std::optional<std::int64_t> last_setpoint_target_inc() const { return last_target_inc_; }

 private:
  struct Setpoint {
    std::int64_t target_raw = 0;   // raw plant frame
    std::int64_t target_user = 0;  // unwrapped user units
    double velocity = 0;           // inc/s
    bool relative = false;
    bool blend = false;  // bit 9: change on set-point
    bool clamped = false;
  };

  Setpoint build(std::uint16_t cw, bool starts_now) const;
  void accept(std::uint16_t cw);
  void plan(const Setpoint& sp, const Setpoint* next);
  double end_velocity(const Setpoint& sp, const Setpoint* next) const;
  double vmax_of(const Setpoint& sp) const;
  bool idle() const;
  void start_halt();
  void release_halt();

  CoreContext& ctx_;
  std::optional<Setpoint> active_;
  std::deque<Setpoint> buffer_;
  std::optional<Setpoint> interrupted_;
  bool ack_ = false;
  std::uint64_t ack_time_ = 0;
  bool halted_ = false;
  bool reached_ = false;
  bool limit_ = false;
  WindowTimer reached_timer_;
  std::int64_t reference_user_ = 0;
  std::optional<std::int64_t> last_target_inc_;
};

}  // namespace mcemu::core
