// How a FAULHABER MotionController reports the drive core's fault causes (faulhaber.md §7.3): EMCY
// code, bit of the FAULHABER error word 2320h and error-register byte (class bit + bit 0). The
// core keeps its own fault state in the 1002h bit layout of drive/faults.hpp; this table only
// changes what the drive shows and sends. Pure data.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "drive/core_types.hpp"

namespace mcemu::core::faulhaber {

struct FhFault {
  FaultCause cause;
  std::uint16_t code;  // EMCY error code, 603Fh, 1003h
  int error_bit;       // bit of 2320h; -1: none (warnings of the core)
  std::uint8_t reg;    // 1001h contribution: class bit | bit 0
};

// The temperature warning of faulhaber.md §7.3: EMCY 43F0h, 2320h bit 4, register 0x03. The core
// has no such cause; DriveCore raises it while the rounded winding temperature is ≥ 100 °C.
inline constexpr std::uint16_t k_temperature_warning_code = 0x43F0;
inline constexpr int k_temperature_warning_bit = 4;
inline constexpr std::uint8_t k_temperature_warning_reg = 0x03;
inline constexpr std::int64_t k_temperature_warning_deg_c = 100;

const FhFault& fh_fault(FaultCause cause);
// The name of a FAULHABER EMCY code (faulhaber.md §7.3; mcemu's words, after the 2320h bit it goes
// with): "following error" for 8611h; "unknown" for a code the table does not have.
std::string_view error_name(std::uint16_t code);
// 2320h for the core's 1002h-layout fault bits (bits 0–13; warnings ignored) and the warning.
std::uint16_t error_word(std::uint32_t fault_bits, bool temperature_warning);
// 1001h for the same: OR of the raised causes' register bytes and the warning's.
std::uint8_t error_register(std::uint32_t fault_bits, bool temperature_warning);
// The 5 manufacturer bytes of a FAULHABER EMCY: 2320h little endian, then 0, 0, 0 (faulhaber.md §5
// command 0x07: code, register, error word, 0 × 3).
std::array<std::uint8_t, 5> emcy_data(std::uint16_t error_word);

}  // namespace mcemu::core::faulhaber
