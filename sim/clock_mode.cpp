#include "sim/clock_mode.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace mcemu::sim {

const char* ClockMode::name() const {
  switch (kind) {
    case Kind::real: return "real";
    case Kind::scaled: return "scaled";
    case Kind::manual: return "manual";
  }
  return "real";
}

ClockMode parse_clock_mode(std::string_view text) {
  const auto bad = [] { return std::invalid_argument("expected real, manual or scaled:X with 0.1 <= X <= 1000"); };
  if (text == "real") return {};
  if (text == "manual") return ClockMode{ClockMode::Kind::manual, 0.0};
  constexpr std::string_view prefix = "scaled:";
  if (text.substr(0, prefix.size()) != prefix) throw bad();
  const std::string number(text.substr(prefix.size()));
  // digits with at most one decimal point; no sign, exponent, hex, inf or nan
  if (number.empty() || number.find_first_not_of("0123456789.") != std::string::npos ||
      number.find('.') != number.rfind('.') || number == ".") {
    throw bad();
  }
  const double x = std::strtod(number.c_str(), nullptr);
  if (!std::isfinite(x) || x < k_min_scale || x > k_max_scale) throw bad();
  return ClockMode{ClockMode::Kind::scaled, x};
}

}  // namespace mcemu::sim
