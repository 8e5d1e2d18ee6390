// The status snapshot of web.md §8.2 (GET /api/v1/status and every WebSocket "status" message),
// the live footer strings of §4.2 and the error-code names of §5.1.
//
// PURE: everything is computed from the values passed in; nothing is read behind the caller's back.
// The footer functions take plain numbers (table-driven tests use the manual's examples); the
// snapshot builder reads the objects it needs from the dictionary and takes the rest — drive time
// and state, the plant's actual velocity, script, RefGo, UDP and LED state — as plain values.
// StatusSnapshots numbers the snapshots (`seq`: +1 per snapshot built, never repeated).
#pragma once

#include <array>
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
  bool operator==(const PythonStatus&) const = default;
};
struct RefgoStatus {
  int clients = 0;
  int attach_mode = 0;  // 0 = no script attached (refgo.md §5.1)
  std::int64_t repeat_way = 0;
  std::uint32_t wait_time_ms = 0;
  bool back_and_forth = false;
  std::optional<std::uint64_t> jog_timer_ms;  // time left until the timed jog stops
  bool operator==(const RefgoStatus&) const = default;
};
struct LedStatus {
  bool green = false;
  bool yellow = false;
  bool operator==(const LedStatus&) const = default;
};

// The FAULHABER MotionController (faulhaber.md): what its snapshot adds.
struct FaulhaberStatus {
  int basic_running = 0;                      // the running MC BASIC slot, 0 = none
  std::optional<std::uint32_t> basic_line;    // its running line
  int basic_autostart = 0;                    // the autostart slot, 0 = none
  std::optional<std::int64_t> temperature_c;  // the drive's temperature, °C (the MC has no 3401h)
  bool operator==(const FaulhaberStatus&) const = default;
};

// The bicolour status LED of the MC (web/README.md "FAULHABER drive", mcemu's choice): green steady
// in Operation enabled, green blinking in the other powered states, red in Fault and Fault reaction
// active, off in Not ready to switch on. FAULHABER's red blink codes are not modelled.
struct FhLed {
  std::string_view color;  // "green", "red", "off"
  bool blink = false;
};
FhLed fh_led(core::PdsState s);
// "Operation enabled", "Switch on disabled", … (CiA 402 state names)
std::string_view state_name(core::PdsState s);

// The footer of a FAULHABER drive: the CiA 402 state (with H4(603Fh) in Fault), the statusword, the
// mode, the MC BASIC state, position 6064h, velocity 606Ch (min⁻¹) and the digital I/O of 2311h.
struct FhFooterValues {
  core::PdsState state = core::PdsState::not_ready_to_switch_on;
  std::uint16_t error_code = 0;     // 603Fh
  std::uint16_t statusword = 0;     // 6041h
  std::int8_t op_mode_display = 0;  // 6061h
  int basic_running = 0;            // slot, 0 = none
  std::int64_t pos = 0;             // 6064h
  std::int64_t vel = 0;             // 606Ch
  std::uint16_t inputs = 0;         // 2311h.01, bit n−1 = DigIn n
  std::uint16_t outputs = 0;        // 2311h.03, bit n−1 = DigOut n
  int input_count = 8;
  int output_count = 2;
};
struct FhFooter {
  std::string state, statwd, opmode, basic, pos, vel, io;
};
FhFooter fh_footer(const FhFooterValues& v);

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
  // Set on a FAULHABER drive: the snapshot then has the MC's footer and LED and leaves out the
  // MovingCap's python, refgo, udp, ts/tpsr/live and its two Morse/link LEDs.
  std::optional<FaulhaberStatus> faulhaber{};
  int input_count = 8;   // FAULHABER: DigIn1…n
  int output_count = 2;  // FAULHABER: DigOut1…n
};

// The snapshot object without "type" (the WebSocket adds "type": "status").
std::string status_json(const StatusInputs& in, std::uint64_t seq);

// Every snapshot has the next seq (web.md §8.2) and the current drive time, but its body is built
// only when something else it shows changed since the last one — a value of the dictionary (its
// generation), the state, or one of the inputs from outside the dictionary — and shared by every
// request and WebSocket subscriber until then; the seq and the time are spliced in (issue 26:
// status at the speed of the socket; an idle drive's time moves every tick).
class StatusSnapshots {
 public:
  std::string build(const StatusInputs& in);
  std::uint64_t last_seq() const { return seq_; }
  std::uint64_t bodies_built() const { return built_; }  // how often the body was built (tests)

 private:
  struct Key {
    std::uint64_t generation = 0;
    core::PdsState state = core::PdsState::not_ready_to_switch_on;
    double velocity_inc_s = 0;
    bool temperature_available = true;
    PythonStatus python{};
    RefgoStatus refgo{};
    int udp_listeners = 0;
    LedStatus led{};
    std::string script_id;                     // 3500h.01 is a read hook (the engine's script), no stored value
    std::optional<FaulhaberStatus> faulhaber;  // MC BASIC's state lives outside the dictionary
    int input_count = 0;
    int output_count = 0;
    bool operator==(const Key&) const = default;
  };
  std::uint64_t seq_ = 0;
  std::uint64_t built_ = 0;
  std::optional<Key> key_;
  // The body around its two values that change without a rebuild, the seq and the drive time:
  // parts_[0] <first> parts_[1] <second> parts_[2].
  std::array<std::string, 3> parts_;
  bool time_first_ = false;
};

}  // namespace mcemu::web::api
