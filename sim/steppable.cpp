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
  for (Steppable* d : drives_) {
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
