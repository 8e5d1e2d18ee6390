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
  settled_.push_back(ticks_);
}

// Asked only of a settled drive (after its step, or settled by the touch that forgot the answer):
// its answer counts from its own time.
std::uint64_t Fleet::quiet_through(std::size_t i) const {
  if (quiet_through_[i] == k_unknown) {
    const std::uint64_t q = drives_[i]->quiet_steps();
    quiet_through_[i] = q >= k_forever - settled_[i] ? k_forever : settled_[i] + q;
  }
  return quiet_through_[i];
}

// The drive was quiet through every tick it was left behind (Fleet::step left it only then).
void Fleet::settle_one(std::size_t i) {
  if (settled_[i] < ticks_) drives_[i]->skip(ticks_ - settled_[i]);
  settled_[i] = ticks_;
}

void Fleet::step() {
  const std::size_t n = drives_.size();
  // Hints only for drives that step in this tick (a quiet one is not visited); an unknown answer
  // (k_unknown = 0) most likely means a step.
  const auto steps_now = [this](std::size_t k) { return quiet_through_[k] <= ticks_; };
  for (std::size_t i = 0; i < n; ++i) {
    if (n >= prefetch_from_) {
      if (const std::size_t k = i + k_prefetch_levels + 1; k < n && steps_now(k)) __builtin_prefetch(drives_[k]);
      for (int level = 0; level < k_prefetch_levels; ++level) {
        const std::size_t k = i + static_cast<std::size_t>(k_prefetch_levels - level);
        if (k < n && steps_now(k)) drives_[k]->prefetch(level);
      }
    }
    if (quiet_through(i) > ticks_) continue;  // left behind: settled when it next steps or is read
    settle_one(i);
    drives_[i]->step();
    settled_[i] = ticks_ + 1;
    quiet_through_[i] = k_unknown;
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

// Every drive is quiet through the stretch (n ≤ quiet_steps()): what each owes and the stretch in one skip.
void Fleet::skip(std::uint64_t n) {
  ticks_ += n;
  settle();
}

void Fleet::settle() {
  for (std::size_t i = 0; i < drives_.size(); ++i) settle_one(i);
}

// From outside a step, where a caller may already have changed the drive without settling it first
// (a contract breach): advance() then asks the drive, which steps in full what it can no longer skip.
void Fleet::settle_drive(Steppable& drive) {
  if (const auto it = index_.find(&drive); it != index_.end()) settle_outside(it->second);
}

void Fleet::settle_outside(std::size_t i) {
  if (settled_[i] < ticks_ && advance(*drives_[i], ticks_ - settled_[i]).full > 0) quiet_through_[i] = k_unknown;
  settled_[i] = ticks_;
}

void Fleet::touch() {
  for (std::size_t i = 0; i < drives_.size(); ++i) settle_outside(i);
  for (Steppable* d : drives_) d->touch();
  quiet_through_.assign(quiet_through_.size(), k_unknown);
}

void Fleet::touch_drive(Steppable& drive) {
  const auto it = index_.find(&drive);
  if (it == index_.end()) return drive.touch();
  settle_outside(it->second);
  drive.touch();
  quiet_through_[it->second] = k_unknown;
}

}  // namespace mcemu::sim
