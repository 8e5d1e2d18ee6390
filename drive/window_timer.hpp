// "Has held for … ms" (drive-core.md §7.9): with s0 the first step of an unbroken run of steps in
// which a condition holds, the timer reports true from the end of step s0 + hold_ms on.
#pragma once

#include <cstdint>
#include <optional>

namespace mcemu::core {

class WindowTimer {
 public:
  void restart() { start_.reset(); }
  // Called once per step (step 8 of §2.4) with the step's time.
  bool update(bool condition, std::uint64_t now_ms, std::uint64_t hold_ms) {
    if (!condition) {
      start_.reset();
      return false;
    }
    if (!start_) start_ = now_ms;
    return now_ms >= *start_ + hold_ms;
  }

 private:
  std::optional<std::uint64_t> start_;
};

}  // namespace mcemu::core
