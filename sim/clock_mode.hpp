// The --clock flag (spec README "Command line", web.md §8.1/§8.10): how drive time follows wall
// time. Pure value + parser.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace mcemu::sim {

struct ClockMode {
  enum class Kind : std::uint8_t { real, scaled, manual };
  Kind kind = Kind::real;
  double scale = 1.0;  // drive time per wall time: 1 (real), X (scaled), 0 (manual)

  // "real", "scaled", "manual" (web.md §8.1 clock.mode)
  const char* name() const;
};

// "real", "scaled:X" with 0.1 ≤ X ≤ 1000 (a decimal number), "manual". nullopt-like failure as
// std::invalid_argument with the accepted forms, for the caller's usage error.
ClockMode parse_clock_mode(std::string_view text);

inline constexpr double k_min_scale = 0.1;
inline constexpr double k_max_scale = 1000.0;
inline constexpr std::uint64_t k_max_advance_ms = 3600000;  // POST /api/v1/clock/advance (web.md §8.10)

}  // namespace mcemu::sim
