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

void Fleet::step() {
  const std::size_t n = drives_.size();
  for (std::size_t i = 0; i < n; ++i) {
    Steppable* d = drives_[i];
    if (i + k_prefetch_levels + 1 < n) __builtin_prefetch(drives_[i + k_prefetch_levels + 1]);
    for (int level = 0; level < k_prefetch_levels; ++level) {
      const std::size_t k = i + static_cast<std::size_t>(k_prefetch_levels - level);
      if (k < n) drives_[k]->prefetch(level);
    }
    if (d->quiet_steps() > 0) {
      d->skip(1);
    } else {
      d->step();
    }
  }
}

std::uint64_t Fleet::quiet_steps() const {
  std::uint64_t q = k_forever;
  for (const Steppable* d : drives_) {
    q = std::min(q, d->quiet_steps());
    if (q == 0) break;
  }
  return q;
}

void Fleet::skip(std::uint64_t n) {
  for (Steppable* d : drives_) d->skip(n);
}

void Fleet::touch() {
  for (Steppable* d : drives_) d->touch();
}

}  // namespace mcemu::sim
