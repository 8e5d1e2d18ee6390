#include "drive/scaling.hpp"

#include <cmath>
#include <limits>

namespace mcemu::core {
namespace {

// __int128 is a GCC/Clang extension; the brief allows it for exact scaling (§3.3).
__extension__ using u128 = unsigned __int128;

constexpr u128 k_limit = u128{1} << 63;

u128 gcd128(u128 a, u128 b) {
  while (b != 0) {
    const u128 t = a % b;
    a = b;
    b = t;
  }
  return a;
}

struct Ratio {
  u128 n;
  u128 d;
};

Ratio reduce(const FactorGroup& fg) {
  const u128 n = u128{fg.motor_rev} * fg.gear_shaft * fg.feed;
  const u128 d = u128{fg.encoder_inc} * fg.gear_motor * fg.feed_shaft;
  if (n == 0 || d == 0) return {n, d};
  const u128 g = gcd128(n, d);
  return {n / g, d / g};
}

}  // namespace

std::int64_t mul_div_round(std::int64_t x, std::uint64_t num, std::uint64_t den) {
  const bool neg = x < 0;
  const u128 mag = neg ? u128{static_cast<std::uint64_t>(-(x + 1))} + 1 : u128{static_cast<std::uint64_t>(x)};
  const u128 q = (2 * mag * num + den) / (u128{2} * den);
  constexpr u128 max_pos = static_cast<u128>(std::numeric_limits<std::int64_t>::max());
  if (neg) {
    if (q > max_pos) return std::numeric_limits<std::int64_t>::min();
    return -static_cast<std::int64_t>(q);
  }
  if (q > max_pos) return std::numeric_limits<std::int64_t>::max();
  return static_cast<std::int64_t>(q);
}

std::int64_t round_half_away(double v) {
  if (std::isnan(v)) return 0;
  if (v >= 9.2e18) return std::numeric_limits<std::int64_t>::max();
  if (v <= -9.2e18) return std::numeric_limits<std::int64_t>::min();
  return std::llround(v);
}

std::int64_t floor_mod(std::int64_t x, std::int64_t m) {
  const std::int64_t r = x % m;
  return r < 0 ? r + m : r;
}

std::int32_t wrap_i32(std::int64_t v) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(v)); }

od::AbortCode Scaling::check(const FactorGroup& fg) {
  if (fg.encoder_inc == 0 || fg.motor_rev == 0 || fg.gear_motor == 0 || fg.gear_shaft == 0 || fg.feed == 0 ||
      fg.feed_shaft == 0) {
    return od::AbortCode::value_too_low;
  }
  const Ratio r = reduce(fg);
  if (r.n >= k_limit || r.d >= k_limit) return od::AbortCode::value_too_high;
  return od::AbortCode::none;
}

Scaling::Scaling(const FactorGroup& fg, model::Kind kind, AccelUnit unit) : fg_(fg), kind_(kind), unit_(unit) {
  const Ratio r = reduce(fg);
  n_ = static_cast<std::uint64_t>(r.n);
  d_ = static_cast<std::uint64_t>(r.d);
  rpm_ = kind_ == model::Kind::rotary && n_ == d_;
  negate_position_ = (fg.polarity & 0x80) != 0;
  negate_velocity_ = (fg.polarity & 0x40) != 0;
}

std::int64_t Scaling::to_user(std::int64_t inc) const {
  const std::int64_t u = mul_div_round(inc, n_, d_);
  return negate_position_ ? -u : u;
}

std::int64_t Scaling::to_inc(std::int64_t user) const { return mul_div_round(negate_position_ ? -user : user, d_, n_); }

std::int64_t Scaling::distance_to_inc(std::int64_t user) const { return mul_div_round(user, d_, n_); }

std::int64_t Scaling::distance_to_user(std::int64_t inc) const { return mul_div_round(inc, n_, d_); }

double Scaling::velocity_to_inc_s(double value) const {
  if (rpm_) return value * static_cast<double>(fg_.encoder_inc) / (60.0 * static_cast<double>(fg_.motor_rev));
  return value * static_cast<double>(d_) / static_cast<double>(n_);
}

double Scaling::target_velocity_to_inc_s(double value) const {
  return velocity_to_inc_s(negate_velocity_ ? -value : value);
}

double Scaling::velocity_units(double inc_s) const {
  if (rpm_) return inc_s * 60.0 * static_cast<double>(fg_.motor_rev) / static_cast<double>(fg_.encoder_inc);
  return inc_s * static_cast<double>(n_) / static_cast<double>(d_);
}

std::int64_t Scaling::velocity_from_inc_s(double inc_s) const {
  const std::int64_t v = round_half_away(velocity_units(inc_s));
  return negate_velocity_ ? -v : v;
}

double Scaling::acceleration_to_inc_s2(double value) const {
  if (kind_ == model::Kind::rotary) {
    return value * static_cast<double>(fg_.encoder_inc) * static_cast<double>(unit_.num) /
           (static_cast<double>(unit_.den) * static_cast<double>(fg_.motor_rev));
  }
  return value * 1000.0 * static_cast<double>(d_) / static_cast<double>(n_);
}

double Scaling::jerk_to_inc_s3(double value) const { return acceleration_to_inc_s2(value); }

double Scaling::speed_limit_to_inc_s(double value) const {
  if (kind_ == model::Kind::rotary) {
    return value * static_cast<double>(fg_.encoder_inc) / (60.0 * static_cast<double>(fg_.motor_rev));
  }
  return value * 1000.0;
}

std::int64_t Scaling::revolution_user() const {
  const std::int64_t r = mul_div_round(1, fg_.feed, fg_.feed_shaft);
  return r < 1 ? 1 : r;
}

}  // namespace mcemu::core
