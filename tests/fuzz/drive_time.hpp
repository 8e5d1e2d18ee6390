// Drive time of one fuzz input on a real drive bundle, advanced as the server's manual clock
// advances it (docs/clock.md, sim::advance): quiet stretches are skipped in one call, every step
// that is needed runs in full. By the contract of sim/steppable.hpp this leaves exactly the state
// 1 ms stepping leaves (tests/server/idle_equivalence_test.cpp compares the two); the targets now
// fuzz that contract too, as the server relies on it. A client's action touches the drive (the
// server's wake after every receive, FIN and write completion), so the step after it is a full one.
//
// Budget per input: at most `max_ms` of drive time; once it is spent, further advances do nothing.
#pragma once

#include <algorithm>
#include <cstdint>

#include "sim/drive_steps.hpp"
#include "sim/steppable.hpp"

namespace mcemu::fuzz {

class DriveTime {
 public:
  DriveTime(sim::DriveSteps& steps, std::uint64_t max_ms) : steps_(steps), max_ms_(max_ms) {}

  // A client acted between steps: the next step is a full one.
  void touch() { steps_.touch(); }
  // Up to `ms` of drive time, within the budget.
  void advance(std::uint64_t ms) {
    ms = std::min(ms, max_ms_ - ms_);
    if (ms == 0) return;
    const sim::Advanced r = sim::advance(steps_, ms);
    ms_ += r.steps;
  }
  std::uint64_t ms() const { return ms_; }  // advanced so far

 private:
  sim::DriveSteps& steps_;
  std::uint64_t max_ms_;
  std::uint64_t ms_ = 0;
};

}  // namespace mcemu::fuzz
