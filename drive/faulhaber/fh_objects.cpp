#include "drive/faulhaber/fh_objects.hpp"

namespace mcemu::core::faulhaber {

FhHandles FhHandles::resolve(const od::ObjectDictionary& od) {
  const auto h = [&](std::uint16_t i, std::uint8_t s) { return od.handle(i, s); };
  FhHandles r{};
  r.negative_mask = h(0x2310, 0x01);
  r.positive_mask = h(0x2310, 0x02);
  r.polarity = h(0x2310, 0x10);
  r.logical_inputs = h(0x2311, 0x01);
  r.physical_inputs = h(0x2311, 0x02);
  r.output_state = h(0x2311, 0x03);
  r.outputs = h(0x2311, 0x04);
  r.error_word = h(0x2320, 0x00);
  r.emcy_mask = h(0x2321, 0x01);
  r.device_status = h(0x2324, 0x01);
  r.limit_check_delay = h(0x2324, 0x02);
  r.max_torque = h(0x6072, 0);
  r.torque_limit_positive = h(0x60E0, 0);
  r.torque_limit_negative = h(0x60E1, 0);
  r.torque_actual = h(0x6077, 0);
  return r;
}

InputState evaluate_inputs(std::uint16_t physical, std::uint16_t pins, const InputConfig& config) {
  InputState s;
  s.physical = static_cast<std::uint16_t>(physical & pins);
  s.logical = static_cast<std::uint16_t>((s.physical ^ config.polarity) & pins);
  s.limit_negative = (s.logical & config.negative_mask) != 0;
  s.limit_positive = (s.logical & config.positive_mask) != 0;
  return s;
}

std::uint16_t apply_output_command(std::uint16_t state, std::uint16_t command, std::uint16_t outputs) {
  std::uint16_t next = state;
  for (int k = 0; k < 8; ++k) {
    const auto bit = static_cast<std::uint16_t>(1u << k);
    if (!(outputs & bit)) continue;
    switch ((command >> (2 * k)) & 0x3) {
      case 0x0: next = static_cast<std::uint16_t>(next & ~bit); break;
      case 0x1: next = static_cast<std::uint16_t>(next | bit); break;
      case 0x2: next = static_cast<std::uint16_t>(next ^ bit); break;
      default: break;
    }
  }
  return static_cast<std::uint16_t>(next & outputs);
}

std::uint32_t device_status_word(const DeviceStatus& s) {
  std::uint32_t w = 0;
  const auto set = [&w](bool on, int bit) {
    if (on) w |= 1u << bit;
  };
  set(s.following_error, 5);
  set(s.limit_positive, 6);
  set(s.limit_negative, 7);
  set(s.soft_limit_positive, 8);
  set(s.soft_limit_negative, 9);
  set(s.torque_limited, 14);
  set(s.temperature_warning, 16);
  set(s.temperature_error, 17);
  set(s.over_voltage, 18);
  set(s.under_voltage, 19);
  return w;
}

}  // namespace mcemu::core::faulhaber
