// The fault catalogue of drive-core.md §11.1: 1002h bit, EMCY code, error-register byte, reaction,
// reset rule and name of every cause. Pure data plus small helpers; the state lives in DriveCore.
// The one place the 13 fault names and codes are written: the web pages (web.md §5.1) and the UDP
// notes (udp-debug.md §4.7) ask fault_name().
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "drive/core_types.hpp"

namespace mcemu::core {

enum class FaultKind : std::uint8_t {
  monitored,  // a physical condition (supply, temperature, I²t) checked at step 3; injection overrides it
  injected,   // present while injected (inject … clear)
  event,      // raised once per occurrence, reset allowed at once
  warning     // 1002h bit ≥ 16, follows its condition, no fault
};

struct FaultInfo {
  FaultCause cause;
  int bit;             // 1002h bit
  std::uint16_t code;  // EMCY code (0 for warnings)
  std::uint8_t reg;    // error-register byte (1001h)
  bool torque_off;     // reaction forced to "torque off at once" (else 605Eh)
  FaultKind kind;
  std::string_view name;  // "ERROR_STROKE" (empty for the warning, which has no EMCY code)
};

std::span<const FaultInfo> fault_table();
const FaultInfo& fault_info(FaultCause cause);
// The name of the fault with this EMCY code, "UNKNOWN" for a code no fault has.
std::string_view fault_name(std::uint16_t emcy_code);
// OR of the error-register bytes of the error bits (0–13) set in a 1002h value.
std::uint8_t error_register(std::uint32_t bits_1002);
inline constexpr std::uint32_t k_error_bits_mask = 0x0000FFFF;

}  // namespace mcemu::core
