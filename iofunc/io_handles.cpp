#include "iofunc/io_handles.hpp"

namespace mcemu::iofunc {

IoHandles IoHandles::resolve(const od::ObjectDictionary& od) {
  const auto h = [&](std::uint16_t i, std::uint8_t s) { return od.handle(i, s); };
  IoHandles r{};
  r.virtual_inputs = h(0x3510, 1);
  r.command = h(0x3510, 2);
  r.inputs = h(0x60FD, 0);
  r.outputs = h(0x60FE, 1);
  r.statusword = h(0x6041, 0);
  r.mfr_status = h(0x1002, 0);
  r.mode_display = h(0x6061, 0);
  r.supported_modes = h(0x6502, 0);
  r.position_user = h(0x6064, 0);
  r.position_inc = h(0x6063, 0);
  r.demand_inc = h(0x60FC, 0);
  r.position_option = h(0x60F2, 0);
  r.limit_min = h(0x607D, 1);
  r.limit_max = h(0x607D, 2);
  r.quick_stop_option = h(0x605A, 0);
  r.profile_velocity = h(0x6081, 0);
  r.profile_accel = h(0x6083, 0);
  r.profile_decel = h(0x6084, 0);
  r.max_current = h(0x6073, 0);
  r.target_velocity = h(0x60FF, 0);
  r.homing_speed = h(0x6099, 1);
  r.homing_accel = h(0x609A, 0);
  for (std::size_t n = 0; n < r.in.size(); ++n) {
    const auto index = static_cast<std::uint16_t>(0x3511 + n);
    r.in[n] = InputRecord{h(index, 1), h(index, 3), h(index, 4), h(index, 5),   h(index, 6),
                          h(index, 7), h(index, 8), h(index, 9), h(index, 0x0A)};
  }
  for (std::size_t k = 0; k < r.out.size(); ++k) {
    const auto index = static_cast<std::uint16_t>(0x3611 + k);
    r.out[k] = OutputRecord{h(index, 1), h(index, 2), h(index, 3), h(index, 4), h(index, 5), h(index, 6)};
  }
  return r;
}

}  // namespace mcemu::iofunc
