// What the transport fault injections (transport_faults.hpp) do to one unit of output, decided in
// one place for every adapter (web.md §9, slcan-canopen.md §11.3):
// - a RefGo reply: refgo.noReply drops it, refgo.delay holds it back (wall time, order kept);
// - a node frame on the SLCAN bus: slcan.dropTx drops it (for every session), slcan.delayTx holds
//   it back;
// - a UDP datagram: udp.drop drops it.
// DelayLine keeps the held-back units in their order: a unit is released when its time has come
// and every unit before it has been released, so a later unit that was not delayed never overtakes
// an earlier delayed one.
//
// PURE and single-threaded: the adapters pass the wall time (any monotonic clock, in ms) and own
// the timer that calls them back at next_due().
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "device/transport_faults.hpp"

namespace mcemu::device {

struct Verdict {
  enum class Action : std::uint8_t { send, drop, delay };
  Action action = Action::send;
  std::chrono::milliseconds delay{0};  // Action::delay
  std::string fault_id;                // the injection that decided (empty for send)
  TransportKind kind = TransportKind::refgo_no_reply;

  bool operator==(const Verdict&) const = default;
};

// One RefGo reply: refgo.noReply is asked first (a reply not sent is not delayed), then refgo.delay.
Verdict refgo_reply_verdict(TransportFaults& faults);
// One frame the CANopen node sends: slcan.dropTx (matching its identifier) first, then slcan.delayTx.
Verdict node_frame_verdict(TransportFaults& faults, std::uint32_t cob_id);
// One datagram of the UDP debug console: udp.drop.
Verdict udp_datagram_verdict(TransportFaults& faults);

// "reply not sent (fault f3 refgo.noReply)", "frame held back 200 ms (fault f4 slcan.delayTx)".
std::string verdict_text(const Verdict& v, std::string_view what);

template <class T>
class DelayLine {
 public:
  using Ms = std::chrono::milliseconds;

  // Queues `item` to be released at `due`. Returns it at once instead when nothing is waiting
  // and its time has come.
  std::optional<T> push(T item, Ms now, Ms due) {
    if (waiting_.empty() && due <= now) return item;
    waiting_.emplace_back(due, std::move(item));
    return std::nullopt;
  }
  // The items whose time has come, in order, up to the first one still waiting.
  std::vector<T> pop_due(Ms now) {
    std::vector<T> out;
    while (!waiting_.empty() && waiting_.front().first <= now) {
      out.push_back(std::move(waiting_.front().second));
      waiting_.pop_front();
    }
    return out;
  }
  std::optional<Ms> next_due() const {
    if (waiting_.empty()) return std::nullopt;
    return waiting_.front().first;
  }
  bool empty() const { return waiting_.empty(); }
  std::size_t size() const { return waiting_.size(); }
  void clear() { waiting_.clear(); }

 private:
  std::deque<std::pair<Ms, T>> waiting_;
};

}  // namespace mcemu::device
