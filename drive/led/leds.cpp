#include "drive/led/leds.hpp"

namespace mcemu::led {

std::optional<std::uint16_t> fault_status(const core::DriveCore& core, const od::ObjectDictionary& od) {
  const auto s = core.state();
  if (s != core::PdsState::fault && s != core::PdsState::fault_reaction_active) return std::nullopt;
  const auto code = od.read_number(0x603F, 0);
  return static_cast<std::uint16_t>(code ? *code : 0);
}

Ipv4 address_of(const od::ObjectDictionary& od) {
  Ipv4 ip{};  // 0.0.0.0 on a drive without 5007h (FAULHABER)
  for (std::uint8_t s = 1; s <= 4; ++s) {
    if (const auto v = od.read_number(0x5007, s)) ip[s - 1] = static_cast<std::uint8_t>(*v);
  }
  return ip;
}

}  // namespace mcemu::led
