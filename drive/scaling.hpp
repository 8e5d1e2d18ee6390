// Every conversion between user units and internal units (drive-core.md §3). No other code of the
// core multiplies by a gear, feed or encoder value.
//
// Contract: positions are exact — x·N/D is computed in unsigned 128-bit arithmetic and rounded half
// away from zero (§3.3); the reduced N and D are below 2^63 (check() refuses anything else).
// Velocities, accelerations and jerks are doubles in inc/s, inc/s², inc/s³; values reported back
// to the OD are rounded half away from zero. Polarity 607Eh (§3.8) is applied here: bit 7 negates
// user positions, bit 6 negates the signed velocity objects 60FFh, 606Bh and 606Ch.
#pragma once

#include <cstdint>

#include "drive/model/model_preset.hpp"
#include "drive/od/abort_code.hpp"

namespace mcemu::core {

// round(x·num/den), half away from zero, exact; saturates at the int64 range. num, den ≥ 1.
std::int64_t mul_div_round(std::int64_t x, std::uint64_t num, std::uint64_t den);
// std::llround semantics (half away from zero) with saturation instead of undefined behaviour.
std::int64_t round_half_away(double v);
// Floor modulo: result in [0, m) for m > 0.
std::int64_t floor_mod(std::int64_t x, std::int64_t m);
// Two's-complement wrap of a position into the I32 range of its OD entry (§3.4).
std::int32_t wrap_i32(std::int64_t v);

// The factor group and polarity as stored in the OD (608Fh, 6091h, 6092h, 607Eh).
struct FactorGroup {
  std::uint64_t encoder_inc = 65536;  // 608Fh.01
  std::uint64_t motor_rev = 1;        // 608Fh.02
  std::uint64_t gear_motor = 1;       // 6091h.01
  std::uint64_t gear_shaft = 1;       // 6091h.02
  std::uint64_t feed = 65536;         // 6092h.01
  std::uint64_t feed_shaft = 1;       // 6092h.02
  std::uint8_t polarity = 0;          // 607Eh
};

// The rotary acceleration unit in motor revolutions per s² (§3.6; factory 1/36).
struct AccelUnit {
  std::uint64_t num = 1;
  std::uint64_t den = 36;
};

class Scaling {
 public:
  // none, value_too_low (a zero) or value_too_high (reduced N or D reaches 2^63), §3.1.
  static od::AbortCode check(const FactorGroup& fg);

  Scaling() = default;
  // fg must pass check().
  Scaling(const FactorGroup& fg, model::Kind kind, AccelUnit unit);

  // user position of an increment count (polarity bit 7 applied)
  std::int64_t to_user(std::int64_t inc) const;
  // increments of a user position (polarity bit 7 applied)
  std::int64_t to_inc(std::int64_t user) const;
  // increments of a user-unit distance or window (no polarity)
  std::int64_t distance_to_inc(std::int64_t user) const;
  // user-unit distance of a number of increments (no polarity)
  std::int64_t distance_to_user(std::int64_t inc) const;

  // §3.5: true when velocity objects are motor rpm (rotary model and N == D)
  bool rpm_units() const { return rpm_; }
  // magnitude objects (6081h, 6099h, 606Dh, 606Fh, …) → inc/s
  double velocity_to_inc_s(double value) const;
  // 60FFh → inc/s (polarity bit 6)
  double target_velocity_to_inc_s(double value) const;
  // inc/s → 606Bh / 606Ch (polarity bit 6, rounded)
  std::int64_t velocity_from_inc_s(double inc_s) const;
  // inc/s → velocity units as a double (no polarity), for window comparisons
  double velocity_units(double inc_s) const;
  // 6083h, 6084h, 6085h, 609Ah, 60C5h, 60C6h → inc/s² (§3.6)
  double acceleration_to_inc_s2(double value) const;
  // 60A4h → inc/s³ (§3.6)
  double jerk_to_inc_s3(double value) const;
  // 607Fh, 6080h, 3401h.02, 6059h.03 → inc/s (§3.7: not user-scaled)
  double speed_limit_to_inc_s(double value) const;
  // one output revolution in user units, 6092h.01 / 6092h.02 rounded, at least 1 (§7.11)
  std::int64_t revolution_user() const;

  std::uint64_t numerator() const { return n_; }    // N (reduced)
  std::uint64_t denominator() const { return d_; }  // D (reduced)
  const FactorGroup& factor_group() const { return fg_; }

 private:
  FactorGroup fg_;
  model::Kind kind_ = model::Kind::rotary;
  AccelUnit unit_;
  std::uint64_t n_ = 1;
  std::uint64_t d_ = 1;
  bool rpm_ = true;
  bool negate_position_ = false;
  bool negate_velocity_ = false;
};

}  // namespace mcemu::core
