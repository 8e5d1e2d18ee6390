#include "iofunc/output_functions.hpp"

#include <algorithm>

namespace mcemu::iofunc {
namespace {

constexpr std::uint16_t k_bit_coded = 255;

struct Context {
  const OutputConfig& cfg;
  int k;
  const DriveSnapshot& s;
  const core::Scaling& scaling;
};

bool inside(std::int64_t p, std::int64_t a, std::int64_t b) { return std::min(a, b) <= p && p <= std::max(a, b); }

// held(R) of §5.4: −Wl ≤ 6063h − R ≤ Wr, d reduced into one rotary period first.
bool held(std::int64_t reference_inc, const Context& c) {
  std::int64_t d = core::wrap_i32(c.s.position_inc - reference_inc);
  if (c.s.rotary_period_inc && *c.s.rotary_period_inc > 0) {
    const std::int64_t period = *c.s.rotary_period_inc;
    d = core::floor_mod(d + period / 2, period) - period / 2;
  }
  const std::int64_t right = c.cfg.right_distance > 0 ? c.scaling.distance_to_inc(c.cfg.right_distance) : 0;
  const std::int64_t left = c.cfg.left_distance > 0 ? c.scaling.distance_to_inc(c.cfg.left_distance) : 0;
  return -left <= d && d <= right;
}

// The smallest candidate input whose result register 1 is held; 0 if none (§5.5).
int feedback_code(const Context& c) {
  for (int n = 1; n <= 10; ++n) {
    if (((c.s.candidates >> (n - 1)) & 1) && held(c.s.result1[static_cast<std::size_t>(n - 1)], c)) return n;
  }
  return 0;
}

bool statusword_monitor(const Context& c) { return (c.s.statusword & c.cfg.config) != 0; }

bool status_register_monitor(const Context& c) { return (c.s.mfr_status & c.cfg.config) != 0; }

bool limit_monitor(const Context& c) {
  const std::int64_t p = c.s.position_user;
  const auto& r = c.cfg;
  const bool right = (r.config & 1) && inside(p, r.right_position, r.right_position + r.right_distance);
  const bool left = (r.config & 2) && inside(p, r.left_position - r.left_distance, r.left_position);
  return right || left;
}

bool position_reached(const Context& c) {
  const std::uint16_t cfg = c.cfg.config;
  if (cfg == 0) return held(c.s.general_reference_inc, c);
  if (cfg <= 10) return held(c.s.result1[static_cast<std::size_t>(cfg - 1)], c);
  if (cfg == k_bit_coded) return ((feedback_code(c) >> (c.k - 1)) & 1) != 0;
  return false;
}

bool status_ok(const Context& c) { return drive_ok(c.s); }

bool reached_and_ok(const Context& c) { return position_reached(c) && drive_ok(c.s); }

using Evaluator = bool (*)(const Context&);
// Indexed by the function number of 36xxh.01; 0 (manual) has no evaluator.
constexpr std::array<Evaluator, 7> k_functions = {
    nullptr, statusword_monitor, status_register_monitor, limit_monitor, position_reached, status_ok, reached_and_ok};

}  // namespace

bool drive_ok(const DriveSnapshot& s) {
  return (s.statusword & 0x0008) == 0 && (s.statusword & 0x0080) == 0 && (s.mfr_status & 0x3FFF) == 0;
}

bool output_level(const OutputConfig& cfg, int k, const DriveSnapshot& s, const core::Scaling& scaling) {
  if (cfg.function <= 0 || cfg.function >= static_cast<int>(k_functions.size())) return false;
  return k_functions[static_cast<std::size_t>(cfg.function)](Context{cfg, k, s, scaling});
}

}  // namespace mcemu::iofunc
