// Drive time of one fuzz input on a real drive bundle, advanced as the server's manual clock
// advances it (docs/clock.md, sim::advance): quiet stretches are skipped in one call, every step
// that is needed runs in full. By the contract of sim/steppable.hpp this leaves exactly the state
// 1 ms stepping leaves (tests/server/idle_equivalence_test.cpp compares the two); the targets now
// fuzz that contract too, as the server relies on it. A client's action touches the drive (the
// server's wake after every receive, FIN and write completion), so the step after it is a full one.
//
// Budget per input: at most `max_ms` of drive time, of which at most `max_full` ms in full steps.
// Once either is spent, further advances do nothing, except that quiet stretches are still skipped
// after the full steps are spent (an idle drive's timers still run out; a drive that needs a step
// stays where it is). The full steps are what an input costs: ~2 µs each under ASan, against
// ~0.1 ms for building the drive, so a few inputs that keep a drive moving for 20 s would
// otherwise take most of the fuzzer's time.
#pragma once

#include <algorithm>
#include <cstdint>

#include "sim/drive_steps.hpp"
#include "sim/steppable.hpp"

namespace mcemu::fuzz {

// The budget of the whole-drive targets: 20 s lets every timer an input can set run out (SDO
// timeouts, heartbeats, fault-injection durations, LED schedules, RefGo wait times), and a drive
// kept moving still goes through 3 s of motion: a move of the short numbers the ops make settles, a
// Back & Forth goes forth and back, a timed jog ends.
inline constexpr std::uint64_t k_max_ms = 20000;
inline constexpr std::uint64_t k_max_full_ms = 3000;

class DriveTime {
 public:
  explicit DriveTime(sim::DriveSteps& steps, std::uint64_t max_ms = k_max_ms, std::uint64_t max_full = k_max_full_ms)
      : steps_(steps), max_ms_(max_ms), max_full_(max_full) {}

  // A client acted between steps: the next step is a full one.
  void touch() { steps_.touch(); }
  // Up to `ms` of drive time, within the budget.
  void advance(std::uint64_t ms) {
    ms = std::min(ms, max_ms_ - ms_);
    if (ms == 0) return;
    const sim::Advanced r = sim::advance(steps_, ms, max_full_ - full_);
    ms_ += r.steps;
    full_ += r.full;
  }
  std::uint64_t ms() const { return ms_; }      // advanced so far
  std::uint64_t full() const { return full_; }  // of which in full steps

 private:
  sim::DriveSteps& steps_;
  std::uint64_t max_ms_;
  std::uint64_t max_full_;
  std::uint64_t ms_ = 0;
  std::uint64_t full_ = 0;
};

}  // namespace mcemu::fuzz
