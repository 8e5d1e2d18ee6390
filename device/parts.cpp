#include "device/parts.hpp"

#include <algorithm>
#include <chrono>

namespace mcemu::device {

std::uint64_t FaultsPart::quiet_steps() const {
  const auto e = faults_.next_expiry();
  return e ? sim::steps_before(*e, core_.time_ms()) : sim::k_forever;
}

// The samples a quiet stretch passed are all equal (nothing changed): one run, O(1).
void ScopePart::skip(std::uint64_t n) {
  const std::uint64_t now = core_.time_ms();  // after the core's skip
  const std::uint64_t from = now - std::min<std::uint64_t>(n, Scope::k_window_ms) + 1;
  const std::uint64_t first = (from + Scope::k_sample_ms - 1) / Scope::k_sample_ms * Scope::k_sample_ms;
  if (first > now) return;
  const std::uint64_t count = (now - first) / Scope::k_sample_ms + 1;
  scope_.add_run(first, count, scope_.sample_of(od_));
}

std::uint64_t RefgoPart::quiet_steps() const {
  const auto& p = refgo_.programs();
  if (p.back_and_forth_active()) return 0;  // follows the drive every step
  const auto due = p.jog_stop_due_ms();
  return due ? sim::steps_before(*due, core_.time_ms()) : sim::k_forever;
}

std::uint64_t CanopenPart::quiet_steps() const {
  const auto d = bus_.node().next_deadline();
  if (!d) return sim::k_forever;
  const auto now = bus_.now().count();
  return d->count() > now ? static_cast<std::uint64_t>(d->count() - now - 1) : 0;
}

void CanopenPart::skip(std::uint64_t n) { bus_.step(std::chrono::milliseconds(static_cast<std::int64_t>(n))); }

void FaulhaberPart::step() { port_.step(faulhaber::Millis(static_cast<std::int64_t>(core_.time_ms()))); }

std::uint64_t FaulhaberPart::quiet_steps() const {
  const auto d = port_.next_deadline();
  return d ? sim::steps_before(static_cast<std::uint64_t>(std::max<std::int64_t>(d->count(), 0)), core_.time_ms())
           : sim::k_forever;
}

void FaulhaberPart::skip(std::uint64_t) { step(); }

}  // namespace mcemu::device
