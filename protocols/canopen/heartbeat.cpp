#include "protocols/canopen/heartbeat.hpp"

namespace mcemu::canopen {

std::int64_t HeartbeatProducer::configured() const { return period_entry_ ? od_.number(*period_entry_) : 0; }

bool HeartbeatProducer::enabled() const { return configured() != 0; }

void HeartbeatProducer::restart(Millis at) {
  period_ = configured();
  next_ = period_ > 0 ? std::optional(at + Millis(period_)) : std::nullopt;
}

void HeartbeatProducer::written(std::int64_t period_ms, Millis now) {
  period_ = period_ms;
  next_ = period_ > 0 ? std::optional(now + Millis(period_)) : std::nullopt;
}

void HeartbeatProducer::resync(Millis now) {
  if (const auto t = configured(); t != period_) written(t, now);
}

void HeartbeatProducer::advance(Millis now, NmtState state, std::uint8_t node_id, Outbox& out) {
  resync(now);
  if (state == NmtState::initialising || !next_ || now < *next_) return;
  const auto byte = static_cast<std::uint8_t>(state);
  out.heartbeat.push_back(make_frame(0x700u + node_id, &byte, 1));
  while (*next_ <= now) *next_ += Millis(period_);
}

std::optional<Millis> HeartbeatProducer::next_deadline() const { return next_; }

}  // namespace mcemu::canopen
