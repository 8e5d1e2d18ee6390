// Heartbeat producer, 1017h (slcan-canopen.md §5.1): one frame 0x700 + n with the NMT state every
// 1017h ms of simulated time; the period starts at the boot-up, and a write of 1017h restarts it at
// the write. A change made without a write hook (bulk load by Restore or reset) is picked up at the
// next advance(). Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "drive/od/dictionary.hpp"
#include "protocols/canopen/types.hpp"

namespace mcemu::canopen {

class HeartbeatProducer {
 public:
  explicit HeartbeatProducer(const od::ObjectDictionary& od) : od_(od), period_entry_(od.find(0x1017, 0)) {}

  void restart(Millis at);                           // boot-up: first heartbeat at + T
  void written(std::int64_t period_ms, Millis now);  // 1017h written: next heartbeat now + T
  void resync(Millis now);                           // picks up a 1017h changed by a bulk load
  // Sends the heartbeat if due (never in INITIALISING).
  void advance(Millis now, NmtState state, std::uint8_t node_id, Outbox& out);
  std::optional<Millis> next_deadline() const;
  bool enabled() const;  // 1017h ≠ 0 (heartbeat and guarding are exclusive)

 private:
  std::int64_t configured() const;

  const od::ObjectDictionary& od_;
  std::optional<od::Handle> period_entry_;  // 1017h, read every step (absent: no heartbeat)
  std::int64_t period_ = 0;                 // ms, as last seen
  std::optional<Millis> next_;
};

}  // namespace mcemu::canopen
