// The two LEDs of one drive (morse-led.md): green STATUS (Morse) and yellow LINK/ACT, plus the rule
// that turns the drive core's state into the green LED's status.
//
// Contract: pure. The composition root owns one Leds per drive and feeds it: power_up() after every
// power on (drive time 0, the address of 5007h after the start-up load), update_status() after every
// drive step and every batch of core events, the yellow inputs from the network side.
#pragma once

#include "drive/drive_core.hpp"
#include "drive/led/link_led.hpp"
#include "drive/led/status_led.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::led {

// 603Fh while the drive is in Fault or Fault reaction active, else nullopt (§2.1; warnings do not
// count).
std::optional<std::uint16_t> fault_status(const core::DriveCore& core, const od::ObjectDictionary& od);
// 5007h.01–.04.
Ipv4 address_of(const od::ObjectDictionary& od);

struct Leds {
  StatusLed green;
  LinkLed yellow;

  void power_up(Ipv4 ip) {
    green.power_up(ip);
    yellow.power_up();
  }
  void update_status(const core::DriveCore& core, const od::ObjectDictionary& od) {
    green.set_status(core.time_ms(), fault_status(core, od));
  }
};

}  // namespace mcemu::led
