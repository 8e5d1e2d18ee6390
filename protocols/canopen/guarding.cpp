#include "protocols/canopen/guarding.hpp"

#include "protocols/canopen/od_access.hpp"

namespace mcemu::canopen {

void NodeGuarding::reset() {
  toggle_ = 0;
  life_deadline_.reset();
}

std::optional<std::uint8_t> NodeGuarding::on_rtr(NmtState state, bool heartbeat_enabled, Millis now) {
  if (state == NmtState::initialising || heartbeat_enabled) return std::nullopt;
  const auto reply = static_cast<std::uint8_t>((toggle_ << 7) | static_cast<std::uint8_t>(state));
  toggle_ ^= 1;
  // 100Ch/100Dh take effect at the RTR.
  const auto guard_ms = stored_number_or(od_, 0x100C, 0, 0);
  const auto factor = stored_number_or(od_, 0x100D, 0, 0);
  if (guard_ms != 0 && factor != 0) {
    life_deadline_ = now + Millis(guard_ms * factor);
  } else {
    life_deadline_.reset();
  }
  return reply;
}

bool NodeGuarding::advance(Millis now, bool heartbeat_enabled) {
  if (heartbeat_enabled) life_deadline_.reset();
  if (!life_deadline_ || now < *life_deadline_) return false;
  life_deadline_.reset();  // re-armed by the next RTR
  return true;
}

}  // namespace mcemu::canopen
