// Events the drive core emits (drive-core.md §13). Plain values, drained with
// DriveCore::drain_events() after every step and every OD write; order = the order they arose.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "drive/core_types.hpp"

namespace mcemu::core {

struct StatuswordChanged {
  std::uint16_t old_value;
  std::uint16_t new_value;
};
// transition = the CiA 402 transition number (0–16); 3+4 is reported once as 4 with from = RTSO.
struct StateChanged {
  PdsState from;
  PdsState to;
  int transition;
};
struct ModeDisplayChanged {
  std::int8_t mode;
};
// One CANopen EMCY message: error code, error register and five manufacturer bytes.
struct Emcy {
  std::uint16_t code;
  std::uint8_t reg;
  std::array<std::uint8_t, 5> data{};
  // The 8 data bytes of the CAN frame (code little endian first).
  std::array<std::uint8_t, 8> bytes() const {
    return {static_cast<std::uint8_t>(code & 0xFF),
            static_cast<std::uint8_t>(code >> 8),
            reg,
            data[0],
            data[1],
            data[2],
            data[3],
            data[4]};
  }
};
struct FaultRaised {
  FaultCause cause;
  std::uint16_t code;
};
struct FaultResetDone {};
struct FaultResetRefused {
  std::vector<FaultCause> causes;  // the causes whose reset condition is still false
};
struct SetpointAccepted {
  std::int64_t target_inc;  // absolute target, position-actual frame (6063h)
  bool buffered;            // queued behind a running segment
};
enum class SetpointRejectReason : std::uint8_t { buffer_full };
struct SetpointRejected {
  SetpointRejectReason reason;
};
struct TargetReached {
  std::int8_t mode;  // 6061h at the time bit 10 rose
};
struct HomingFinished {
  std::int8_t method;
  bool ok;
};
struct InternalLimit {
  bool active;
};
struct InputsChanged {
  std::uint32_t old_value;
  std::uint32_t new_value;
};
struct PowerStage {
  bool on;  // motor torque enabled
};
enum class DiagnosticLevel : std::uint8_t { debug, info, warning };
struct Diagnostic {
  DiagnosticLevel level;
  std::string text;
};

using Event = std::variant<StatuswordChanged, StateChanged, ModeDisplayChanged, Emcy, FaultRaised, FaultResetDone,
                           FaultResetRefused, SetpointAccepted, SetpointRejected, TargetReached, HomingFinished,
                           InternalLimit, InputsChanged, PowerStage, Diagnostic>;

// The event as one line of text for the trace (web.md §8.6, channel drive): its name of §13 and
// its payload, e.g. "StateChanged switched_on -> operation_enabled (transition 4)",
// "Emcy 3221h reg 05h data 2132050000000000", "FaultRaised under_voltage 3221h".
std::string event_text(const Event& e);

}  // namespace mcemu::core
