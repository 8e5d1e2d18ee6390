// Vocabulary shared by the CANopen services: simulated time, NMT states, 8-byte payloads and the
// per-call outbox that fixes the order of frames within one processing call (slcan-canopen.md §2).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <vector>

#include "protocols/can/frame.hpp"

namespace mcemu::canopen {

using Millis = std::chrono::milliseconds;  // simulated time

// Values as sent in boot-up, heartbeat and guarding replies (§4.3).
enum class NmtState : std::uint8_t { initialising = 0x00, stopped = 0x04, operational = 0x05, pre_operational = 0x7F };

using Payload = std::array<std::uint8_t, 8>;

inline can::Frame make_frame(std::uint32_t id, const std::uint8_t* data, std::size_t len) {
  can::Frame f;
  f.id = id & 0x7FF;
  f.dlc = static_cast<std::uint8_t>(len > 8 ? 8 : len);
  for (std::size_t i = 0; i < f.dlc; ++i) f.data[i] = data[i];
  return f;
}

// Frames produced during one processing call, by kind; flattened in the normative order: SDO
// response or abort; boot-up or guarding reply; EMCYs in the order raised; TPDOs in ascending PDO
// number; heartbeat.
struct Outbox {
  std::vector<can::Frame> sdo;
  std::vector<can::Frame> error_control;
  std::vector<can::Frame> emcy;
  std::vector<std::pair<int, can::Frame>> tpdo;  // (PDO number 0…3, frame)
  std::vector<can::Frame> heartbeat;

  bool empty() const {
    return sdo.empty() && error_control.empty() && emcy.empty() && tpdo.empty() && heartbeat.empty();
  }
  std::vector<can::Frame> flatten();  // in the normative order; leaves the outbox empty
};

}  // namespace mcemu::canopen
