// A scripted sim::Steppable for the clock tests: the steps (1-based) listed in `needed` must run,
// every other step is quiet; `busy` makes every step needed. Records what was asked of it.
#pragma once

#include <gtest/gtest.h>

#include <set>

#include "sim/steppable.hpp"

namespace mcemu::sim::test {

struct FakeTarget final : Steppable {
  std::set<std::uint64_t> needed;
  bool busy = false;
  bool dirty = false;
  std::uint64_t t = 0;  // steps advanced
  std::uint64_t fulls = 0;
  std::uint64_t skips = 0;
  std::vector<std::uint64_t> full_at;  // the step numbers that ran in full
  mutable std::uint64_t asked = 0;     // quiet_steps() calls

  void step() override {
    ++t;
    ++fulls;
    full_at.push_back(t);
    dirty = false;
  }
  std::uint64_t quiet_steps() const override {
    ++asked;
    return quiet();
  }
  std::uint64_t quiet() const {
    if (busy || dirty) return 0;
    const auto it = needed.lower_bound(t + 1);
    if (it == needed.end()) return k_forever;
    return *it - t - 1;
  }
  void skip(std::uint64_t n) override {
    EXPECT_LE(n, quiet()) << "skip over a needed step at t = " << t;
    t += n;
    ++skips;
  }
  void touch() override { dirty = true; }
};

}  // namespace mcemu::sim::test
