// What kind of drive a bundle is (design.md "one device, two personalities"): which protocol
// sessions and services the shell builds around it. A personality is a description, not code: the
// bundle (device/device.hpp) builds the sessions it names, server/ binds the listeners it names,
// web/ serves the pages it names. A new drive family is a new row of personalities(), not a copy of
// the bundle.
#pragma once

#include <string_view>

#include "drive/model/model_preset.hpp"

namespace mcemu::device {

struct Personality {
  std::string_view name;  // "movingcap"
  // Sessions the bundle owns, each stepped with the drive.
  bool refgo = false;    // the RefGo interpreter and its programs (refgo.md); TCP --refgo-port
  bool canopen = false;  // the CANopen node on the SLCAN bus (slcan-canopen.md); TCP --slcan-port
  // Services the shell adds.
  bool udp_debug = false;         // the UDP debug console (udp-debug.md); --udp-port
  bool drive_pages = false;       // the MovingCap web pages and /program.html (web.md §2–§6)
  bool code_scripts = false;      // MovingCap CODE scripts (scripting.md)
  bool io_functions = false;      // input/output functions 3510h–361xh (iofunc.md)
  bool morse_status_led = false;  // the STATUS LED's Morse-coded IP (morse-led.md)
};

// The personality of a preset's family.
const Personality& personality_of(const model::ModelPreset& preset);

// The MovingCap Ethernet drive: everything mcemu emulated before the FAULHABER family.
const Personality& movingcap();

}  // namespace mcemu::device
