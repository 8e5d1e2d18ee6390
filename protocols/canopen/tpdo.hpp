// The four transmit PDOs (slcan-canopen.md §9.3–§9.5): synchronous (0…240, 252), RTR-only (253)
// and event-driven (254/255) with inhibit time and event timer; change detection compares the
// payload built from the OD with the last one sent. Active only in OPERATIONAL (the node calls it
// only then). Pure.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "drive/od/dictionary.hpp"
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
    std::optional<std::vector<std::uint8_t>> last;
    std::optional<Millis> last_time;
    int sync_count = 0;
    std::optional<std::vector<std::uint8_t>> sampled;
    std::optional<Millis> due;  // a send is wanted at this time (inhibit end or timer)
  };

  Config config(int n) const;
  std::vector<std::uint8_t> payload(int n) const;
  void send(int n, const Config& c, std::vector<std::uint8_t> data, Millis now, Outbox& out);

  const od::ObjectDictionary& od_;
  std::array<State, 4> state_{};
};

}  // namespace mcemu::canopen
