// What the lint knows about the drive between observations (docs/lint.md §2): the statusword,
// the last controlword and mode written, the target velocity — kept from OdWrite samples, core
// events and PowerOn, never read from the drive. Plus the CiA 402 decoding the rules share.
#pragma once

#include <cstdint>
#include <string_view>

#include "lint/observations.hpp"

namespace mcemu::lint {

// CiA 402 power drive system states as 6041h bits 0–6 show them (drive-core.md §4.1).
enum class Pds : std::uint8_t {
  not_ready_to_switch_on,
  switch_on_disabled,
  ready_to_switch_on,
  switched_on,
  operation_enabled,
  quick_stop_active,
  fault_reaction_active,
  fault
};
Pds pds_of(std::uint16_t statusword);
std::string_view to_string(Pds s);  // "Switch on disabled"

// The state command of a controlword with bit 7 = 0 (drive-core.md §4.2 masks).
enum class Command : std::uint8_t { shutdown, switch_on, enable_operation, disable_voltage, quick_stop };
Command command_of(std::uint16_t controlword);
std::string_view to_string(Command c);  // "Enable operation"
// The state the command leads to from `from` when it acts (the state itself for "stay" commands).
Pds target_of(Command c, Pds from);

struct DriveView {
  std::uint16_t statusword = 0;      // 6041h
  std::uint16_t controlword = 0;     // 6040h, last accepted write
  std::int8_t mode_display = 0;      // 6061h
  std::int8_t mode_command = 0;      // 6060h, last accepted write
  std::int64_t target_velocity = 0;  // 60FFh, last accepted write
  bool target_changed = false;       // 607Ah written since the last rising edge of 6040h bit 4

  Pds state() const { return pds_of(statusword); }
  bool moving() const { return (statusword & 0x0100) != 0; }  // drive-core.md §5 bit 8

  // After the rules have seen the observation.
  void apply(const OdWrite& w);
  void apply(const CoreEvent& e);
  void apply(const PowerOn& p);
};

inline bool accepted(od::AbortCode c) { return c == od::AbortCode::none || c == od::AbortCode::pending; }

}  // namespace mcemu::lint
