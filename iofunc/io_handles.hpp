// The object-dictionary entries iofunc reads and writes (iofunc.md §2, §4.1, §5.1), resolved to
// handles once at construction. Not a copy of any value: every read goes through the dictionary.
#pragma once

#include <array>

#include "drive/od/dictionary.hpp"

namespace mcemu::iofunc {

// Input function record 3511h (IN1) … 351Ah (IN10), iofunc.md §4.1.
struct InputRecord {
  od::Handle function;     // .01 high byte rising, low byte falling
  od::Handle result1;      // .03
  od::Handle result2;      // .04
  od::Handle delay_ms;     // .05
  od::Handle speed;        // .06
  od::Handle accel;        // .07
  od::Handle target;       // .08
  od::Handle decel;        // .09 (homing method for function 7)
  od::Handle max_current;  // .0A
};

// Output function record 3611h (OUT1) … 3614h (OUT4), iofunc.md §5.1.
struct OutputRecord {
  od::Handle function;        // .01
  od::Handle config;          // .02
  od::Handle right_position;  // .03
  od::Handle left_position;   // .04
  od::Handle right_distance;  // .05
  od::Handle left_distance;   // .06
};

struct IoHandles {
  od::Handle virtual_inputs;     // 3510h.01
  od::Handle command;            // 3510h.02
  od::Handle inputs;             // 60FDh
  od::Handle outputs;            // 60FEh.01
  od::Handle statusword;         // 6041h
  od::Handle mfr_status;         // 1002h
  od::Handle mode_display;       // 6061h
  od::Handle supported_modes;    // 6502h
  od::Handle position_user;      // 6064h
  od::Handle position_inc;       // 6063h
  od::Handle demand_inc;         // 60FCh
  od::Handle position_option;    // 60F2h
  od::Handle limit_min;          // 607Dh.01
  od::Handle limit_max;          // 607Dh.02
  od::Handle quick_stop_option;  // 605Ah
  od::Handle profile_velocity;   // 6081h
  od::Handle profile_accel;      // 6083h
  od::Handle profile_decel;      // 6084h
  od::Handle max_current;        // 6073h
  od::Handle target_velocity;    // 60FFh
  od::Handle homing_speed;       // 6099h.01
  od::Handle homing_accel;       // 609Ah
  std::array<InputRecord, 10> in;
  std::array<OutputRecord, 4> out;

  // Throws std::out_of_range when the dictionary lacks one of them (every model has them all).
  static IoHandles resolve(const od::ObjectDictionary& od);
};

}  // namespace mcemu::iofunc
