#include "sim/steppable.hpp"

#include <algorithm>

namespace mcemu::sim {

Advanced advance(Steppable& s, std::uint64_t n, std::uint64_t max_full, const std::function<bool()>& hold) {
  Advanced r;
  while (r.steps < n) {
    const std::uint64_t q = s.quiet_steps();
    if (q > 0) {
      const std::uint64_t k = std::min(q, n - r.steps);
      s.skip(k);
      r.steps += k;
      continue;
    }
    if (r.full >= max_full) break;
    s.step();
    ++r.full;
    ++r.steps;
    if (hold && hold()) break;
  }
  return r;
}

void Fleet::add(Steppable& drive) {
  index_.emplace(&drive, drives_.size());
  drives_.push_back(&drive);
  quiet_through_.push_back(k_unknown);
}

std::uint64_t Fleet::quiet_through(std::size_t i) const {
  if (quiet_through_[i] == k_unknown) {
    const std::uint64_t q = drives_[i]->quiet_steps();
    quiet_through_[i] = q >= k_forever - ticks_ ? k_forever : ticks_ + q;
  }
  return quiet_through_[i];
}

void Fleet::step() {
  const std::size_t n = drives_.size();
  for (std::size_t i = 0; i < n; ++i) {
    Steppable* d = drives_[i];
    if (n >= prefetch_from_) {
      if (i + k_prefetch_levels + 1 < n) __builtin_prefetch(drives_[i + k_prefetch_levels + 1]);
      for (int level = 0; level < k_prefetch_levels; ++level) {
        const std::size_t k = i + static_cast<std::size_t>(k_prefetch_levels - level);
        if (k < n) drives_[k]->prefetch(level);
      }
    }
    if (quiet_through(i) > ticks_) {
      d->skip(1);
    } else {
      d->step();
      quiet_through_[i] = k_unknown;
    }
  }
  ++ticks_;
}

std::uint64_t Fleet::quiet_steps() const {
  std::uint64_t q = k_forever;
  for (std::size_t i = 0; i < drives_.size() && q > 0; ++i) {
    const std::uint64_t through = quiet_through(i);
    if (through != k_forever) q = std::min(q, through > ticks_ ? through - ticks_ : 0);
  }
  return q;
}

void Fleet::skip(std::uint64_t n) {
  for (Steppable* d : drives_) d->skip(n);
  ticks_ += n;
}

void Fleet::touch() {
  for (Steppable* d : drives_) d->touch();
  quiet_through_.assign(quiet_through_.size(), k_unknown);
}

void Fleet::touch_drive(Steppable& drive) {
  drive.touch();
  if (const auto it = index_.find(&drive); it != index_.end()) quiet_through_[it->second] = k_unknown;
}

}  // namespace mcemu::sim
