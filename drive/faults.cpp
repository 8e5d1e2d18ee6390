#include "drive/faults.hpp"

#include <array>

namespace mcemu::core {
namespace {

using C = FaultCause;
using K = FaultKind;

// Names as in the manual (drive-core.md §11.1); the ones the OCR of web.md §5.1 lost are our choice.
constexpr std::array<FaultInfo, k_fault_cause_count> k_table = {{
    {C::over_voltage, 0, 0x3211, 0x05, false, K::monitored, "ERROR_OVER_VOLT"},
    {C::under_voltage, 1, 0x3221, 0x05, true, K::monitored, "ERROR_UNDER_VOLT"},
    {C::ack_error, 2, 0x5200, 0x10, false, K::injected, "ERROR_ACK"},
    {C::over_temperature, 3, 0x4210, 0x09, false, K::monitored, "ERROR_OVER_TEMP"},
    {C::i2t, 4, 0x4220, 0x09, false, K::monitored, "ERROR_DERATING"},
    {C::abort_connection, 5, 0x8130, 0x10, false, K::event, "ERROR_ABORT_CONNECTION"},
    {C::stroke, 6, 0x7121, 0x10, false, K::event, "ERROR_STROKE"},
    {C::motor_communication, 7, 0x7510, 0x10, true, K::injected, "ERROR_COMMUNICATION"},
    {C::sensor, 8, 0xFFF1, 0x10, true, K::injected, "ERROR_SENSOR"},
    {C::hw_sw_enable, 9, 0xFFF2, 0x10, true, K::event, "ERROR_HW_SW_ENABLE"},
    {C::over_current, 11, 0x2220, 0x05, true, K::injected, "ERROR_OVER_CURRENT"},
    {C::external_torque, 12, 0xFFF4, 0x10, false, K::injected, "ERROR_EXT_TORQUE"},
    {C::needs_reset, 13, 0xFFF5, 0x10, true, K::injected, "ERROR_NEEDS_RESET"},
    {C::sensor_warning, 16, 0x0000, 0x00, false, K::warning, ""},
}};

}  // namespace

std::span<const FaultInfo> fault_table() { return k_table; }

const FaultInfo& fault_info(FaultCause cause) { return k_table[static_cast<std::size_t>(cause)]; }

std::string_view fault_name(std::uint16_t emcy_code) {
  for (const auto& f : k_table) {
    if (f.kind != FaultKind::warning && f.code == emcy_code) return f.name;
  }
  return "UNKNOWN";
}

std::uint8_t error_register(std::uint32_t bits_1002) {
  std::uint8_t reg = 0;
  for (const auto& f : k_table) {
    if (f.kind != FaultKind::warning && (bits_1002 & (1u << f.bit))) reg |= f.reg;
  }
  return reg;
}

}  // namespace mcemu::core
