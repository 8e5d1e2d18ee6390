// Homing mode, 6061h = 6 (drive-core.md §9): methods 0, 35, 37 (no motion), −18/−19 (block
// against a mechanical stop), 17 and 19–22 (limit / home switch from 60B8h), 18 when
// homing.enable_method_18 is set; RABBIT models home by 35 only. Status bits 10/12/13 of §9.5.
// FAULHABER drives (faulhaber.md §7.2): 17/18 on the limit switches of 2310h.01/.02, −1…−4 on a
// mechanical stop (−1, −3 negative; −2, −4 positive; no index pulse), 0, 35, 37; no others.
//
// Contract: on_controlword() in the 6040h write (bit-4 start edge, halt), generate() at step 6,
// monitor() at step 8 after 60FDh was recomputed, on_block() from the core's block detector.
// When a reference is found the homing sets ctx.home_offset_inc so that 6063h at the reference
// equals inc(607Ch) (§9.2) and reports it through reference_set() for the core.
#pragma once

#include <array>
#include <cstdint>

#include "drive/core_context.hpp"

namespace mcemu::core {

class Homing {
 public:
  enum class Status : std::uint8_t { idle, in_progress, attained, error };

  explicit Homing(CoreContext& ctx) : ctx_(ctx) {}

  void enter();  // mode entry in OE: not started (001); decelerate if moving
  void abort();  // leaving the mode / OE while running: interrupted
  void on_controlword(std::uint16_t cw, std::uint16_t prev);
  void generate();
  void monitor();
  // The block detector fired while the homing runs. true: consumed (block methods: success).
  // masked: the block was in a phase masked by 3401h.1Ah (a switch search then fails).
  bool on_block(bool masked);

  Status status() const { return status_; }
  bool running() const { return phase_ != Phase::none; }
  bool block_method_running() const { return phase_ == Phase::block; }
  // true once after the core should reset references (demand := actual, integrator, §9.2)
  bool take_reference_set() {
    const bool r = reference_set_;
    reference_set_ = false;
    return r;
  }

 private:
  enum class Phase : std::uint8_t { none, pulse, block, leg, between, final_stop, stopping };
  struct Leg {
    int dir;
    bool fast;          // 6099h.01 (else .02)
    bool until_active;  // stop the leg when the switch becomes active (else inactive)
  };

  void start();
  void fail();
  void succeed();
  void set_reference_here();
  void start_leg();
  void start_block(int dir);
  bool switch_active() const;
  VelocityCommand command(double target) const;

  CoreContext& ctx_;
  Status status_ = Status::idle;
  Phase phase_ = Phase::none;
  std::int8_t method_ = 0;
  int pulse_steps_ = 0;
  std::uint64_t start_ms_ = 0;
  int input_ = 0;  // IN n, or k_negative_limit / k_positive_limit (FAULHABER 2310h.01/.02)
  std::array<Leg, 2> legs_{};
  int leg_count_ = 0;
  int leg_ = 0;
  bool reference_set_ = false;
};

}  // namespace mcemu::core
