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
  std::string_view name;  // "movingcap", "faulhaber"
  // Sessions the bundle owns, each stepped with the drive.
  bool refgo = false;    // the RefGo interpreter and its programs (refgo.md); TCP --refgo-port
  bool canopen = false;  // the CANopen node on the SLCAN bus (slcan-canopen.md); TCP --slcan-port
  // Services the shell adds.
  bool udp_debug = false;         // the UDP debug console (udp-debug.md); --udp-port
  bool drive_pages = false;       // the MovingCap web pages and /program.html (web.md §2–§6)
  bool code_scripts = false;      // MovingCap CODE scripts (scripting.md)
  bool io_functions = false;      // input/output functions 3510h–361xh (iofunc.md)
  bool morse_status_led = false;  // the STATUS LED's Morse-coded IP (morse-led.md)
  bool faulhaber = false;         // the FAULHABER binary RS232 protocol (faulhaber.md §2–§6); --faulhaber-port/-pty
  bool basic = false;             // MC BASIC programs (faulhaber.md §9)
};

// The personality of a preset's family.
const Personality& personality_of(const model::ModelPreset& preset);

// The MovingCap Ethernet drive: RefGo, CANopen over SLCAN, UDP console, its web pages, CODE scripts.
const Personality& movingcap();
// The FAULHABER MotionController V3.0: the binary protocol (TCP and a pseudo-terminal), MC BASIC and
// the JSON API; no RefGo, SLCAN, UDP or MovingCap pages (faulhaber.md §1).
const Personality& faulhaber();

}  // namespace mcemu::device
