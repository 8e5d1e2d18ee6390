#include "drive/led/link_led.hpp"

namespace mcemu::led {

void LinkLed::power_up() {
  flicker_end_.reset();
  quiet_until_.reset();
  edges_.clear();
  led_ = connections_ > 0;
}

void LinkLed::settle(std::uint64_t t) {
  if (flicker_end_ && *flicker_end_ <= t) {
    const std::uint64_t end = *flicker_end_;
    flicker_end_.reset();
    set_led(end, connections_ > 0);
  }
}

void LinkLed::set_led(std::uint64_t t, bool on) {
  if (on == led_) return;
  led_ = on;
  if (!edges_.empty() && edges_.back().first == t) {
    edges_.pop_back();  // the state before it returns: no edge at all
    return;
  }
  edges_.emplace_back(t, on);
  if (edges_.size() > k_max_edges) edges_.pop_front();
}

void LinkLed::connection_opened(std::uint64_t t) {
  settle(t);
  ++connections_;
  set_led(t, flicker_end_ ? connections_ == 0 : true);
}

void LinkLed::connection_closed(std::uint64_t t) {
  settle(t);
  if (connections_ == 0) return;
  --connections_;
  const bool steady = connections_ > 0;
  set_led(t, flicker_end_ ? !steady : steady);
}

void LinkLed::activity(std::uint64_t t) {
  settle(t);
  if (flicker_end_ || (quiet_until_ && t < *quiet_until_)) return;
  flicker_end_ = t + k_flicker_ms;
  quiet_until_ = t + 2 * k_flicker_ms;
  set_led(t, connections_ == 0);
}

bool LinkLed::on(std::uint64_t t) const {
  const bool steady = connections_ > 0;
  if (flicker_end_ && t < *flicker_end_) return !steady;
  return steady;
}

std::vector<LinkLed::Edge> LinkLed::edges(std::uint64_t t) const {
  std::vector<Edge> out;
  for (const Edge& e : edges_) {
    if (e.first <= t) out.push_back(e);
  }
  // the end of a flicker that is over by t, not yet applied by an input
  if (flicker_end_ && *flicker_end_ <= t) {
    const bool steady = connections_ > 0;
    if (steady != led_) {
      if (!out.empty() && out.back().first == *flicker_end_) {
        out.pop_back();
      } else {
        out.emplace_back(*flicker_end_, steady);
        if (out.size() > k_max_edges) out.erase(out.begin());
      }
    }
  }
  return out;
}

}  // namespace mcemu::led
