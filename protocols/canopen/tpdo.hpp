// The four transmit PDOs (slcan-canopen.md §9.3–§9.5): synchronous (0…240, 252), RTR-only (253)
// and event-driven (254/255) with inhibit time and event timer; change detection compares the
// payload built from the OD with the last one sent. Active only in OPERATIONAL (the node calls it
// only then). Pure.
//
// check() runs after every drive step, so what does not change in a step is not redone in it: the
// communication parameters (18xxh) and mappings (1Axxh) are resolved to a Config and handles once
// and again only when the dictionary's settings generation moves. That count covers them: they are
// settings (rw: a master's write, a Store/Restore or reset-communication load) or fixed (const, and
// the ro static mappings no one writes). The payload is built every check, into 8 bytes on the stack.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "protocols/canopen/pdo_map.hpp"
#include "protocols/canopen/types.hpp"

namespace mcemu::canopen {

class TpdoSet {
 public:
  explicit TpdoSet(const od::ObjectDictionary& od) : od_(od) {}

  // Entering OPERATIONAL: counters restart, every valid event-driven TPDO is sent at once.
  void enter_operational(Millis now, Outbox& out);
  void leave_operational();
  void on_sync(Millis now, Outbox& out);
  // A remote frame; true if it addressed a TPDO that answered.
  bool on_rtr(std::uint32_t can_id, Millis now, Outbox& out);
  // Change / event-timer / inhibit-end sends of event-driven TPDOs.
  void check(Millis now, Outbox& out);
  std::optional<Millis> next_deadline() const;

 private:
  struct Config {
    bool exists = false;
    bool valid = false;
    bool rtr_allowed = false;
    std::uint32_t can_id = 0;
    int type = 255;
    Millis inhibit{0};
    Millis event_timer{0};
  };
  struct State {
    std::optional<PdoData> last;
    std::optional<Millis> last_time;
    int sync_count = 0;
    std::optional<PdoData> sampled;
    std::optional<Millis> due;  // a send is wanted at this time (inhibit end or timer)
  };
  struct Pdo {
    Config config;
    ResolvedMap map;  // empty when 1Axxh is absent
  };

  // The resolved TPDO n, refreshed first when the settings generation moved.
  const Pdo& pdo(int n) const;
  const Config& config(int n) const { return pdo(n).config; }
  PdoData payload(int n) const { return build_payload(od_, pdo(n).map); }
  void send(int n, const Config& c, const PdoData& data, Millis now, Outbox& out);

  const od::ObjectDictionary& od_;
  std::array<State, 4> state_{};
  mutable std::array<Pdo, 4> pdos_{};                 // a cache: next_deadline() const reads it too
  mutable std::optional<std::uint64_t> resolved_at_;  // the settings generation pdos_ was resolved at
};

}  // namespace mcemu::canopen
