// "For how many consecutive 1 ms steps has a condition held?" — the debounce of the supply monitors
// (drive-core.md §10.11: under- and over-voltage are raised once the condition has held for 2
// steps). The count saturates instead of overflowing: a supply that stays out of range for weeks
// (an int of ms overflowed after 2³¹ ms ≈ 24.8 days) keeps its fault raised and the drive quiet.
// PURE, header-only.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

namespace mcemu::core {

class StepCount {
 public:
  static constexpr std::uint64_t k_max = std::numeric_limits<std::uint32_t>::max();  // where it stays

  // One step: +1 while the condition holds, back to 0 when it does not.
  void step(bool condition) { count_ = condition ? std::min(count_ + 1, k_max) : 0; }
  // n steps in one go (a quiet stretch skipped, sim/README.md), the condition unchanged throughout.
  void skip(bool condition, std::uint64_t n) { count_ = condition ? count_ + std::min(n, k_max - count_) : 0; }
  void reset() { count_ = 0; }

  std::uint64_t value() const { return count_; }
  bool at_least(std::uint64_t steps) const { return count_ >= steps; }

 private:
  std::uint64_t count_ = 0;
};

}  // namespace mcemu::core
