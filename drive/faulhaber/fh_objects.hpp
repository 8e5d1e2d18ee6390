// The FAULHABER objects the drive core maintains (faulhaber.md §8): digital inputs and limit
// switches (2310h, 2311h.01/.02), digital outputs (2311h.03/.04), error word 2320h, device status
// 2324h.01, torque limits and actual torque (6072h, 60E0h, 60E1h, 6077h). The handles, plus the
// pure rules DriveCore applies to them (drive/drive_core_faulhaber.cpp).
#pragma once

#include <cstdint>

#include "drive/od/dictionary.hpp"

namespace mcemu::core::faulhaber {

struct FhHandles {
  od::Handle negative_mask, positive_mask, polarity;                                   // 2310h.01, .02, .10
  od::Handle logical_inputs, physical_inputs, output_state, outputs;                   // 2311h.01 … .04
  od::Handle error_word, emcy_mask;                                                    // 2320h.00, 2321h.01
  od::Handle device_status, limit_check_delay;                                         // 2324h.01, .02
  od::Handle max_torque, torque_limit_positive, torque_limit_negative, torque_actual;  // 6072h 60E0h 60E1h 6077h

  // Throws std::out_of_range when the dictionary is not a FAULHABER one.
  static FhHandles resolve(const od::ObjectDictionary& od);
};

struct InputConfig {
  std::uint16_t negative_mask = 0;  // 2310h.01: bit n−1 = DigIn n
  std::uint16_t positive_mask = 0;  // 2310h.02
  std::uint16_t polarity = 0;       // 2310h.10: bit set = input active low
};

struct InputState {
  std::uint16_t physical = 0;  // 2311h.02
  std::uint16_t logical = 0;   // 2311h.01 = physical XOR polarity, on the existing inputs only
  bool limit_negative = false;
  bool limit_positive = false;
};

// physical: bit n−1 = the wire level of DigIn n; pins: bit per existing input.
InputState evaluate_inputs(std::uint16_t physical, std::uint16_t pins, const InputConfig& config);

// 2311h.04: two bits per output k (bits 2k+1…2k for DigOut k+1): 01 on, 00 off, 10 toggle,
// 11 unchanged. Returns the new output state (bit k = DigOut k+1), on the existing outputs only.
std::uint16_t apply_output_command(std::uint16_t state, std::uint16_t command, std::uint16_t outputs);

// What 2324h.01 shows (faulhaber.md §8; the other bits stay 0).
struct DeviceStatus {
  bool following_error = false;      // bit 5
  bool limit_positive = false;       // bit 6
  bool limit_negative = false;       // bit 7
  bool soft_limit_positive = false;  // bit 8
  bool soft_limit_negative = false;  // bit 9
  bool torque_limited = false;       // bit 14
  bool temperature_warning = false;  // bit 16
  bool temperature_error = false;    // bit 17
  bool over_voltage = false;         // bit 18
  bool under_voltage = false;        // bit 19
};
std::uint32_t device_status_word(const DeviceStatus& s);

}  // namespace mcemu::core::faulhaber
