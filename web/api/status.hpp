// The status snapshot of web.md §8.2 (GET /api/v1/status and every WebSocket "status" message),
// the live footer strings of §4.2 and the error-code names of §5.1.
//
// PURE: everything is computed from the values passed in; nothing is read behind the caller's back.
// The footer functions take plain numbers (table-driven tests use the manual's examples); the
// snapshot builder reads the objects it needs from the dictionary and takes the rest — drive time
// and state, the plant's actual velocity, script, RefGo, UDP and LED state — as plain values.
// StatusSnapshots numbers the snapshots (`seq`: +1 per snapshot built, never repeated).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "drive/core_types.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::web::api {

// ---- §5.1: names of the error codes shown on the Info page and in `lastError` (the fault
// catalogue's, drive/faults.hpp)
struct ErrorName {
  std::uint16_t code;
  std::string_view name;
};
std::span<const ErrorName> error_names();
// The name of an EMCY code, "UNKNOWN" for a code not in the table.
std::string_view error_name(std::uint16_t code);
// "7121h / ERROR_STROKE"
std::string last_error_text(std::uint16_t code);

// ---- §4.2: the footer strings
struct FooterValues {
  int ts = 0;                                 // RefGo TS: 0 OFF, 1 RDY, 2 MOV, 9 ERR
  std::uint16_t error_code = 0;               // 603Fh
  std::uint16_t statusword = 0;               // 6041h
  std::int8_t op_mode_display = 0;            // 6061h
  std::string_view python_state = "OFF";      // OFF, RUN, BRK
  bool autostart = false;                     // 3500h.04
  std::int64_t pos_user = 0;                  // 6064h
  std::int64_t pos_inc = 0;                   // 6063h
  std::int64_t vel_user = 0;                  // 606Ch
  std::int64_t vel_rpm = 0;                   // motor rpm (motor_rpm())
  std::optional<std::int64_t> temperature_c;  // 3401h.0A; nullopt without a sensor
  std::uint32_t inputs = 0;                   // 60FDh
  std::uint32_t outputs = 0;                  // 60FEh.01
};

struct Footer {
  std::string live, statwd, opmode, python, pos, vel, temp, io;
};
Footer footer(const FooterValues& v);

// "OFF", "RDY", "MOV", "ERR" of a TS value.
std::string_view live_word(int ts);
// Motor rpm of an actual velocity in inc/s: v · 60 · 608Fh.02 / 608Fh.01, rounded half away from
// zero (drive-core.md §3.3); negated when 607Eh bit 6 (velocity polarity) is set, like 606Ch.
std::int64_t motor_rpm(double velocity_inc_s, std::int64_t encoder_inc, std::int64_t motor_revs, bool negate);
// "NRTSO", "SOD", "RTSO", "SO", "OE", "QSA", "FRA", "F"
std::string_view state_abbreviation(core::PdsState s);

// ---- §8.2: the snapshot
struct PythonStatus {
  std::string state = "OFF";  // OFF, RUN, BRK (scripting.md §3)
  int line = 0;
};
struct RefgoStatus {
  int clients = 0;
  int attach_mode = 0;  // 0 = no script attached (refgo.md §5.1)
  std::int64_t repeat_way = 0;
  std::uint32_t wait_time_ms = 0;
  bool back_and_forth = false;
  std::optional<std::uint64_t> jog_timer_ms;  // time left until the timed jog stops
};
struct LedStatus {
  bool green = false;
  bool yellow = false;
};

struct StatusInputs {
  const od::ObjectDictionary& od;
  std::uint64_t time_ms = 0;
  core::PdsState state = core::PdsState::not_ready_to_switch_on;
  double velocity_inc_s = 0;  // the plant's actual velocity (for velRpm)
  bool temperature_available = true;
  PythonStatus python{};
  RefgoStatus refgo{};
  int udp_listeners = 0;
  LedStatus led{};
};

// The snapshot object without "type" (the WebSocket adds "type": "status").
std::string status_json(const StatusInputs& in, std::uint64_t seq);

class StatusSnapshots {
 public:
  // Builds the next snapshot (seq + 1).
  std::string build(const StatusInputs& in) { return status_json(in, ++seq_); }
  std::uint64_t last_seq() const { return seq_; }

 private:
  std::uint64_t seq_ = 0;
};

}  // namespace mcemu::web::api
