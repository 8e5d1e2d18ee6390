// Node guarding and life guarding, 100Ch/100Dh (slcan-canopen.md §5.2): a remote frame on
// 0x700 + n is answered with toggle bit and NMT state; the life time 100Ch × 100Dh, restarted by
// every guarding RTR, expires once per arming. Exclusive with the heartbeat (the node passes
// whether 1017h ≠ 0). Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "drive/od/dictionary.hpp"
#include "protocols/canopen/types.hpp"

namespace mcemu::canopen {

class NodeGuarding {
 public:
  explicit NodeGuarding(const od::ObjectDictionary& od) : od_(od) {}

  void reset();  // boot-up: toggle 0, life guarding inactive until the next RTR
  // The reply byte to a guarding RTR, or nullopt when none is due.
  std::optional<std::uint8_t> on_rtr(NmtState state, bool heartbeat_enabled, Millis now);
  // true once when the life time has expired.
  bool advance(Millis now, bool heartbeat_enabled);
  void cancel_life_guarding() { life_deadline_.reset(); }
  std::optional<Millis> next_deadline() const { return life_deadline_; }

 private:
  const od::ObjectDictionary& od_;
  int toggle_ = 0;
  std::optional<Millis> life_deadline_;
};

}  // namespace mcemu::canopen
