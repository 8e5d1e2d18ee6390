// The green STATUS LED (morse-led.md §2, §3, §6.2): the message "MC+IP<a>+<b>+<c>+<d>[+ERRxxxx]:" in
// Morse code, repeated without end from drive time 0 (power-up).
//
// Contract: pure, single-threaded. The LED needs no step: its state at drive time t is computed from
// the schedule of the repetition that contains t. The caller reports the drive's status with
// set_status() whenever it may have changed (after every drive step and every batch of core events);
// times never go backwards except through power_up(). A repetition's message is the status in force
// at its start time (a change reported at time t applies to a repetition starting at t); a repetition
// in progress is always completed (§2.3).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "drive/led/morse.hpp"

namespace mcemu::led {

using Ipv4 = std::array<std::uint8_t, 4>;
// [drive time ms, on]
using Edge = std::pair<std::uint64_t, bool>;

class StatusLed {
 public:
  static constexpr std::uint32_t k_unit_ms = 120;  // §3.1
  static constexpr std::uint64_t k_max_window_ms = 600000;

  // Powered up at drive time 0 with the address `ip` (5007h after the start-up load).
  explicit StatusLed(Ipv4 ip = {192, 168, 2, 150});

  // "MC+IP192+168+2+150:" or, with a fault code, "MC+IP192+168+2+150+ERR7121:" (§2.1).
  static std::string message(Ipv4 ip, std::optional<std::uint16_t> fault_code);

  // Power cycle: the repetition in progress ends; the message of `ip` starts at drive time 0 (§2.3).
  void power_up(Ipv4 ip);
  // The drive's status at drive time t: the 603Fh code while in Fault or Fault reaction active,
  // nullopt otherwise. Only a change is recorded.
  void set_status(std::uint64_t t, std::optional<std::uint16_t> fault_code);

  // What §6.2 reports at drive time t.
  struct View {
    std::uint64_t cycle_start_ms = 0;
    std::shared_ptr<const Schedule> schedule;  // of the repetition containing t
    std::shared_ptr<const Schedule> next;      // the message starting at cycle_start + cycle if it differs, else null
    bool on = false;
  };
  View view(std::uint64_t t) const;
  bool on(std::uint64_t t) const { return view(t).on; }
  // The edges [time, on] in from_ms … to_ms (inclusive) of the repetition containing `t`, extended
  // periodically both ways as if the message never changed (§6.2 greenEdges); none before time 0.
  // The caller limits the window (≤ k_max_window_ms).
  std::vector<Edge> edges(std::uint64_t t, std::int64_t from_ms, std::int64_t to_ms) const;

  Ipv4 ip() const { return ip_; }

 private:
  std::shared_ptr<const Schedule> schedule_for(std::optional<std::uint16_t> code) const;

  Ipv4 ip_;
  std::shared_ptr<const Schedule> normal_;       // the message without status
  std::uint64_t start_ = 0;                      // start of the last repetition materialised
  std::shared_ptr<const Schedule> current_;      // its message
  std::optional<std::uint16_t> status_;          // latest status reported
  std::shared_ptr<const Schedule> status_text_;  // message of status_
};

}  // namespace mcemu::led
