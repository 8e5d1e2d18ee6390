#include "drive/faulhaber/fh_faults.hpp"

#include "drive/faults.hpp"

namespace mcemu::core::faulhaber {
namespace {

using C = FaultCause;

// faulhaber.md §7.3 [fact: CANMAN Tab. 9–10] for over/under-voltage, over-temperature, following
// error/block (the core's stroke cause) and encoder/sensor; the other rows are choices
// (docs/decisions/0008): i2t is FAULHABER's thermal model, hence the over-temperature row; causes
// a FAULHABER MC has no counterpart for report "internal hardware error" (bit 7, code 5000h).
constexpr std::array<FhFault, k_fault_cause_count> k_table = {{
    {C::over_voltage, 0x3210, 2, 0x05},
    {C::under_voltage, 0x3220, 3, 0x05},
    {C::ack_error, 0x5000, 7, 0x81},
    {C::over_temperature, 0x4310, 5, 0x09},
    {C::i2t, 0x4310, 5, 0x09},
    {C::abort_connection, 0x8130, 11, 0x11},
    {C::stroke, 0x8611, 1, 0x21},
    {C::motor_communication, 0x5000, 7, 0x81},
    {C::sensor, 0x7300, 6, 0x81},
    {C::hw_sw_enable, 0xFF00, 14, 0x81},
    {C::over_current, 0x2300, 7, 0x03},
    {C::external_torque, 0x8611, 1, 0x21},
    {C::needs_reset, 0x5000, 7, 0x81},
    {C::sensor_warning, 0x0000, -1, 0x00},
}};

struct CodeName {
  std::uint16_t code;
  std::string_view name;
};
constexpr std::array<CodeName, 10> k_names{{
    {0x2300, "current error"},
    {0x3210, "over-voltage"},
    {0x3220, "under-voltage"},
    {0x4310, "temperature error"},
    {k_temperature_warning_code, "temperature warning"},
    {0x5000, "internal hardware error"},
    {0x7300, "encoder error"},
    {0x8130, "communication error"},
    {0x8611, "following error"},
    {0xFF00, "safety monitor"},
}};

}  // namespace

const FhFault& fh_fault(FaultCause cause) { return k_table[static_cast<std::size_t>(cause)]; }

std::string_view error_name(std::uint16_t code) {
  for (const auto& n : k_names) {
    if (n.code == code) return n.name;
  }
  return "unknown";
}

std::uint16_t error_word(std::uint32_t fault_bits, bool temperature_warning) {
  std::uint16_t word = temperature_warning ? std::uint16_t{1u << k_temperature_warning_bit} : std::uint16_t{0};
  for (const FaultInfo& f : fault_table()) {
    const FhFault& fh = fh_fault(f.cause);
    if (f.kind != FaultKind::warning && fh.error_bit >= 0 && (fault_bits & (1u << f.bit))) {
      word = static_cast<std::uint16_t>(word | (1u << fh.error_bit));
    }
  }
  return word;
}

std::uint8_t error_register(std::uint32_t fault_bits, bool temperature_warning) {
  std::uint8_t reg = temperature_warning ? k_temperature_warning_reg : std::uint8_t{0};
  for (const FaultInfo& f : fault_table()) {
    if (f.kind != FaultKind::warning && (fault_bits & (1u << f.bit))) reg |= fh_fault(f.cause).reg;
  }
  return reg;
}

std::array<std::uint8_t, 5> emcy_data(std::uint16_t error_word) {
  return {static_cast<std::uint8_t>(error_word & 0xFF), static_cast<std::uint8_t>(error_word >> 8), 0, 0, 0};
}

}  // namespace mcemu::core::faulhaber
