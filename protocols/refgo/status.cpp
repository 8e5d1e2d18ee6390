#include "protocols/refgo/status.hpp"

namespace mcemu::refgo {

PowerState power_state(std::uint16_t sw) {
  if ((sw & 0x4F) == 0x00) return PowerState::nrtso;
  if ((sw & 0x4F) == 0x40) return PowerState::sod;
  if ((sw & 0x4F) == 0x0F) return PowerState::fra;
  if ((sw & 0x4F) == 0x08) return PowerState::f;
  switch (sw & 0x6F) {
    case 0x21: return PowerState::rtso;
    case 0x23: return PowerState::so;
    case 0x27: return PowerState::oe;
    case 0x07: return PowerState::qsa;
    default: return PowerState::nrtso;
  }
}

bool power_stage_on(PowerState s) {
  return s == PowerState::so || s == PowerState::oe || s == PowerState::qsa || s == PowerState::fra;
}

std::uint32_t tpsr(std::uint16_t sw) {
  std::uint32_t r = 0x002;
  if (sw & 0x0008) r |= 0x001;
  if (sw & 0x0100) r |= 0x004;
  if (sw & 0x0400) r |= 0x008;
  if (power_stage_on(power_state(sw))) r |= 0x100;
  return r;
}

int simple_status(std::uint32_t t) {
  if (t & 0x001) return 9;
  if (!(t & 0x100)) return 0;
  if (t & 0x004) return 2;
  return 1;
}

std::string tell_input(std::uint32_t inputs, int n) { return (inputs >> (15 + n)) & 1U ? "1" : "0"; }

std::string tell_inputs(std::uint32_t inputs) {
  static constexpr char k_hex[] = "0123456789abcdef";
  const std::uint32_t v = (inputs >> 16) & 0x3FF;
  std::string out(4, '0');
  for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(3 - i)] = k_hex[(v >> (4 * i)) & 0xF];
  return out;
}

}  // namespace mcemu::refgo
