// The yellow LINK/ACT LED (morse-led.md §5): steady on while at least one counted client connection
// is open; every activity event inverts it for 40 ms, ignored while a flicker shows and for 40 ms
// after it, so a busy link blinks at 12.5 Hz at most. The last 64 state changes are kept (§6.2).
//
// Contract: pure, single-threaded, no step needed. Inputs come with their drive time, never going
// backwards except through power_up(); the server decides which connections and traffic count
// (§5.1, §5.2). State changes of zero duration (two at the same drive time) are not edges.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

namespace mcemu::led {

class LinkLed {
 public:
  static constexpr std::uint64_t k_flicker_ms = 40;
  static constexpr std::size_t k_max_edges = 64;
  using Edge = std::pair<std::uint64_t, bool>;

  // Power cycle: drive time restarts at 0; edges and a flicker in progress are forgotten, open
  // connections stay open (they belong to the network side).
  void power_up();
  void connection_opened(std::uint64_t t);
  void connection_closed(std::uint64_t t);  // ignored when none is open
  void activity(std::uint64_t t);

  bool on(std::uint64_t t) const;
  std::size_t connections() const { return connections_; }
  // The last 64 state changes at or before t, oldest first.
  std::vector<Edge> edges(std::uint64_t t) const;

 private:
  void settle(std::uint64_t t);  // applies the end of a flicker that is over at t
  void set_led(std::uint64_t t, bool on);

  std::size_t connections_ = 0;
  std::optional<std::uint64_t> flicker_end_;  // a flicker shows in [end − 40, end)
  std::optional<std::uint64_t> quiet_until_;  // no new flicker before this time
  bool led_ = false;                          // as of the last input
  std::deque<Edge> edges_;
};

}  // namespace mcemu::led
