#include "drive/led/leds.hpp"

namespace mcemu::led {

std::optional<std::uint16_t> fault_status(const core::DriveCore& core, const od::ObjectDictionary& od) {
  const auto s = core.state();
  if (s != core::PdsState::fault && s != core::PdsState::fault_reaction_active) return std::nullopt;
  return static_cast<std::uint16_t>(od.number(0x603F, 0));
}

Ipv4 address_of(const od::ObjectDictionary& od) {
  Ipv4 ip{};
  for (std::uint8_t s = 1; s <= 4; ++s) ip[s - 1] = static_cast<std::uint8_t>(od.number(0x5007, s));
  return ip;
}

}  // namespace mcemu::led
