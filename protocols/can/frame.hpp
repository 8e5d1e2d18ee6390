// A classic CAN frame as a plain value: the type shared by the SLCAN codec/session (which knows
// CAN frames but not CANopen) and the CANopen node (which knows frames and the OD, not SLCAN).
#pragma once

#include <array>
#include <cstdint>

namespace mcemu::can {

struct Frame {
  std::uint32_t id = 0;   // 11-bit (0…0x7FF) or, with extended, 29-bit identifier
  bool extended = false;  // 29-bit identifier
  bool rtr = false;       // remote transmission request (no data)
  std::uint8_t dlc = 0;   // 0…8; the number of data bytes of a data frame
  std::array<std::uint8_t, 8> data{};

  friend bool operator==(const Frame&, const Frame&) = default;
};

}  // namespace mcemu::can
