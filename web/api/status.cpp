#include "web/api/status.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "drive/faulhaber/fh_faults.hpp"
#include "drive/faults.hpp"
#include "drive/od/objects.hpp"
#include "protocols/refgo/status.hpp"
#include "web/api/http_util.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

std::string fh_last_error_text(std::uint16_t code) {
  return h4(code) + " / " + std::string(core::faulhaber::error_name(code));
}

std::int64_t num(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::int64_t fallback = 0) {
  const auto v = od.read_number(index, sub);
  return v ? *v : fallback;
}

std::string str(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
  const auto v = od.read(index, sub);
  if (v && std::holds_alternative<std::string>(*v)) return std::get<std::string>(*v);
  return {};
}

}  // namespace

// The fault catalogue's names (drive/faults.hpp), by EMCY code.
std::span<const ErrorName> error_names() {
  static const std::vector<ErrorName> names = [] {
    std::vector<ErrorName> out;
    for (const auto& f : core::fault_table()) {
      if (f.kind != core::FaultKind::warning) out.push_back({f.code, f.name});
    }
    return out;
  }();
  return names;
}

std::string_view error_name(std::uint16_t code) { return core::fault_name(code); }

std::string last_error_text(std::uint16_t code) { return h4(code) + " / " + std::string(error_name(code)); }

std::string_view live_word(int ts) {
  switch (ts) {
    case 0: return "OFF";
    case 1: return "RDY";
    case 2: return "MOV";
    default: return "ERR";
  }
}

std::int64_t motor_rpm(double velocity_inc_s, std::int64_t encoder_inc, std::int64_t motor_revs, bool negate) {
  if (encoder_inc <= 0) return 0;
  const double rpm = velocity_inc_s * 60.0 * static_cast<double>(motor_revs) / static_cast<double>(encoder_inc);
  if (!std::isfinite(rpm)) return 0;
  constexpr double k_limit = static_cast<double>(std::numeric_limits<std::int32_t>::max());
  const auto r = static_cast<std::int64_t>(std::llround(std::fmax(-k_limit, std::fmin(k_limit, rpm))));
  return negate ? -r : r;
}

std::string_view state_abbreviation(core::PdsState s) {
  switch (s) {
    case core::PdsState::not_ready_to_switch_on: return "NRTSO";
    case core::PdsState::switch_on_disabled: return "SOD";
    case core::PdsState::ready_to_switch_on: return "RTSO";
    case core::PdsState::switched_on: return "SO";
    case core::PdsState::operation_enabled: return "OE";
    case core::PdsState::quick_stop_active: return "QSA";
    case core::PdsState::fault_reaction_active: return "FRA";
    case core::PdsState::fault: break;
  }
  return "F";
}

Footer footer(const FooterValues& v) {
  Footer f;
  f.live = "MC Live " + std::string(live_word(v.ts));
  if (v.ts == 9) f.live += " " + h4(v.error_code);
  f.statwd = "StatWd " + h4(v.statusword);
  f.opmode = "OpMode " + std::to_string(v.op_mode_display);
  f.python = "Python " + std::string(v.python_state) + (v.autostart ? "/A" : "");
  f.pos = v.pos_user == v.pos_inc ? "Pos " + std::to_string(v.pos_inc) + " inc"
                                  : "Pos " + std::to_string(v.pos_user) + " usr/ " + std::to_string(v.pos_inc) + " inc";
  f.vel = v.vel_user == v.vel_rpm ? "Vel " + std::to_string(v.vel_rpm) + " rpm"
                                  : "Vel " + std::to_string(v.vel_user) + " usr/ " + std::to_string(v.vel_rpm) + " rpm";
  f.temp = v.temperature_c ? "Temp " + std::to_string(*v.temperature_c) +
                                 "\xC2\xB0"
                                 "C"
                           : "Temp";
  f.io = "I";
  for (int n = 1; n <= 10; ++n) f.io += ((v.inputs >> (15 + n)) & 1U) ? static_cast<char>('0' + n % 10) : '.';
  f.io += 'O';
  for (int n = 1; n <= 4; ++n) f.io += ((v.outputs >> (15 + n)) & 1U) ? static_cast<char>('0' + n) : '.';
  return f;
}

std::string_view state_name(core::PdsState s) {
  switch (s) {
    case core::PdsState::not_ready_to_switch_on: return "Not ready to switch on";
    case core::PdsState::switch_on_disabled: return "Switch on disabled";
    case core::PdsState::ready_to_switch_on: return "Ready to switch on";
    case core::PdsState::switched_on: return "Switched on";
    case core::PdsState::operation_enabled: return "Operation enabled";
    case core::PdsState::quick_stop_active: return "Quick stop active";
    case core::PdsState::fault_reaction_active: return "Fault reaction active";
    case core::PdsState::fault: break;
  }
  return "Fault";
}

FhLed fh_led(core::PdsState s) {
  switch (s) {
    case core::PdsState::not_ready_to_switch_on: return {"off", false};
    case core::PdsState::operation_enabled: return {"green", false};
    case core::PdsState::fault_reaction_active:
    case core::PdsState::fault: return {"red", false};
    default: return {"green", true};
  }
}

FhFooter fh_footer(const FhFooterValues& v) {
  FhFooter f;
  f.state = std::string(state_name(v.state));
  if (v.state == core::PdsState::fault || v.state == core::PdsState::fault_reaction_active) {
    f.state += " " + h4(v.error_code);
  }
  f.statwd = "StatWd " + h4(v.statusword);
  f.opmode = "OpMode " + std::to_string(v.op_mode_display);
  f.basic = v.basic_running ? "BASIC RUN " + std::to_string(v.basic_running) : std::string("BASIC OFF");
  f.pos = "Pos " + std::to_string(v.pos) + " inc";
  f.vel = "Vel " + std::to_string(v.vel) + " rpm";
  f.io = "I";
  for (int n = 1; n <= v.input_count; ++n) f.io += ((v.inputs >> (n - 1)) & 1U) ? static_cast<char>('0' + n % 10) : '.';
  f.io += 'O';
  for (int n = 1; n <= v.output_count; ++n)
    f.io += ((v.outputs >> (n - 1)) & 1U) ? static_cast<char>('0' + n % 10) : '.';
  return f;
}

namespace {

// The snapshot of a FAULHABER drive: the CiA 402 part every drive has, the MC's objects, its LED
// and footer; nothing of RefGo, UDP, CODE scripts or the MovingCap's LEDs.
std::string fh_status_json(const StatusInputs& in, std::uint64_t seq) {
  const auto& od = in.od;
  const auto& fh = *in.faulhaber;
  FhFooterValues fv;
  fv.state = in.state;
  fv.error_code = static_cast<std::uint16_t>(num(od, 0x603F, 0));
  fv.statusword = static_cast<std::uint16_t>(num(od, 0x6041, 0));
  fv.op_mode_display = static_cast<std::int8_t>(num(od, 0x6061, 0));
  fv.basic_running = fh.basic_running;
  fv.pos = num(od, 0x6064, 0);
  fv.vel = num(od, 0x606C, 0);
  fv.inputs = static_cast<std::uint16_t>(num(od, 0x2311, 1));
  fv.outputs = static_cast<std::uint16_t>(num(od, 0x2311, 3));
  fv.input_count = in.input_count;
  fv.output_count = in.output_count;
  const FhFooter f = fh_footer(fv);
  const FhLed led = fh_led(in.state);

  json last_error = nullptr;
  if (num(od, 0x1003, 0) > 0) {
    const auto code = static_cast<std::uint32_t>(num(od, 0x1003, 1));
    last_error = json{{"code", code}, {"text", fh_last_error_text(static_cast<std::uint16_t>(code & 0xFFFF))}};
  }
  const json j{
      {"seq", seq},
      {"timeMs", in.time_ms},
      {"personality", "faulhaber"},
      {"state", state_abbreviation(in.state)},
      {"stateName", state_name(in.state)},
      {"statusword", fv.statusword},
      {"controlword", num(od, 0x6040, 0)},
      {"opMode", num(od, 0x6060, 0)},
      {"opModeDisplay", fv.op_mode_display},
      {"errorCode", fv.error_code},
      {"lastError", last_error},
      {"errorRegister", num(od, 0x1001, 0)},
      {"errorWord", num(od, 0x2320, 0)},
      {"deviceStatus", num(od, 0x2324, 1)},
      {"posUser", fv.pos},
      {"posInc", fv.pos},
      {"velUser", fv.vel},
      {"velRpm", fv.vel},
      {"targetPos", num(od, 0x607A, 0)},
      {"temperatureC", fh.temperature_c ? json(*fh.temperature_c) : json(nullptr)},
      {"digIn", num(od, 0x2311, 2)},
      {"digInLogical", fv.inputs},
      {"digOut", fv.outputs},
      {"basic",
       {{"running", fh.basic_running},
        {"line", fh.basic_line ? json(*fh.basic_line) : json(nullptr)},
        {"autostart", fh.basic_autostart}}},
      {"led", {{"color", led.color}, {"blink", led.blink}}},
      {"footer",
       {{"state", f.state},
        {"statwd", f.statwd},
        {"opmode", f.opmode},
        {"basic", f.basic},
        {"pos", f.pos},
        {"vel", f.vel},
        {"io", f.io}}},
  };
  return dump_json(j);
}

}  // namespace

std::string status_json(const StatusInputs& in, std::uint64_t seq) {
  if (in.faulhaber) return fh_status_json(in, seq);
  const auto& od = in.od;
  const auto statusword = static_cast<std::uint16_t>(num(od, od::k_statusword, 0));
  const int ts = refgo::simple_status(refgo::tpsr(statusword));
  const auto error_code = static_cast<std::uint16_t>(num(od, od::k_error_code, 0));
  const auto polarity = num(od, od::k_polarity, 0);
  const bool autostart = num(od, od::k_script, od::k_script_autostart) != 0;
  std::string script_id = str(od, od::k_script, od::k_script_id);
  if (script_id.empty()) script_id = "(empty)";

  FooterValues fv;
  fv.ts = ts;
  fv.error_code = error_code;
  fv.statusword = statusword;
  fv.op_mode_display = static_cast<std::int8_t>(num(od, od::k_mode_display, 0));
  fv.python_state = in.python.state;
  fv.autostart = autostart;
  fv.pos_user = num(od, od::k_position, 0);
  fv.pos_inc = num(od, od::k_position_inc, 0);
  fv.vel_user = num(od, od::k_velocity, 0);
  fv.vel_rpm = motor_rpm(in.velocity_inc_s, num(od, od::k_encoder_resolution, 1, 65536),
                         num(od, od::k_encoder_resolution, 2, 1), (polarity & 0x40) != 0);
  if (in.temperature_available) fv.temperature_c = num(od, od::k_gateway, od::k_gateway_temperature);
  fv.inputs = static_cast<std::uint32_t>(num(od, od::k_digital_inputs, 0));
  fv.outputs = static_cast<std::uint32_t>(num(od, od::k_digital_outputs, 1));
  const Footer f = footer(fv);

  json last_error = nullptr;
  if (num(od, od::k_error_history, 0) > 0) {
    const auto code = static_cast<std::uint32_t>(num(od, od::k_error_history, 1));
    last_error = json{{"code", code}, {"text", last_error_text(static_cast<std::uint16_t>(code & 0xFFFF))}};
  }

  json j{
      {"seq", seq},
      {"timeMs", in.time_ms},
      {"state", state_abbreviation(in.state)},
      {"live", live_word(ts)},
      {"ts", ts},
      {"tpsr", refgo::tpsr(statusword)},
      {"statusword", statusword},
      {"controlword", num(od, od::k_controlword, 0)},
      {"opMode", num(od, od::k_mode, 0)},
      {"opModeDisplay", fv.op_mode_display},
      {"errorCode", error_code},
      {"lastError", last_error},
      {"mfrStatus", num(od, od::k_mfr_status, 0)},
      {"posUser", fv.pos_user},
      {"posInc", fv.pos_inc},
      {"velUser", fv.vel_user},
      {"velRpm", fv.vel_rpm},
      {"targetPos", num(od, od::k_target_position, 0)},
      {"current", num(od, od::k_current, 0)},
      {"temperatureC", fv.temperature_c ? json(*fv.temperature_c) : json(nullptr)},
      {"inputs", fv.inputs},
      {"virtualInputs", num(od, od::k_io_simulation, od::k_virtual_inputs)},
      {"outputs", fv.outputs},
      {"python", {{"state", in.python.state}, {"autostart", autostart}, {"id", script_id}, {"line", in.python.line}}},
      {"refgo",
       {{"clients", in.refgo.clients},
        {"attachMode", in.refgo.attach_mode},
        {"repeatWay", in.refgo.repeat_way},
        {"waitTimeMs", in.refgo.wait_time_ms},
        {"backAndForth", in.refgo.back_and_forth},
        {"jogTimerMs", in.refgo.jog_timer_ms ? json(*in.refgo.jog_timer_ms) : json(nullptr)}}},
      {"udp", {{"listeners", in.udp_listeners}}},
      {"led", {{"green", in.led.green}, {"yellow", in.led.yellow}}},
      {"footer",
       {{"live", f.live},
        {"statwd", f.statwd},
        {"opmode", f.opmode},
        {"python", f.python},
        {"pos", f.pos},
        {"vel", f.vel},
        {"temp", f.temp},
        {"io", f.io}}},
  };
  return dump_json(j);
}

std::string StatusSnapshots::build(const StatusInputs& in) {
  const Key key{in.od.generation(),
                in.state,
                in.velocity_inc_s,
                in.temperature_available,
                in.python,
                in.refgo,
                in.udp_listeners,
                in.led,
                str(in.od, 0x3500, 1),
                in.faulhaber,
                in.input_count,
                in.output_count};
  if (!key_ || !(*key_ == key)) {
    // The body with a seq and a drive time no snapshot has, split around both: a later snapshot
    // only splices its seq and the drive time in (the time moves every tick, the rest rarely).
    constexpr std::uint64_t k_seq_marker = 0xFFFFFFFFFFFFFFFFULL;
    constexpr std::uint64_t k_time_marker = 0xFFFFFFFFFFFFFFFEULL;
    StatusInputs marked = in;
    marked.time_ms = k_time_marker;
    const std::string text = status_json(marked, k_seq_marker);
    const std::size_t seq_at = text.find(std::to_string(k_seq_marker));
    const std::size_t time_at = text.find(std::to_string(k_time_marker));
    const std::size_t width = std::to_string(k_seq_marker).size();  // both markers have 20 digits
    time_first_ = time_at < seq_at;
    const std::size_t first = std::min(seq_at, time_at);
    const std::size_t second = std::max(seq_at, time_at);
    parts_[0] = text.substr(0, first);
    parts_[1] = text.substr(first + width, second - first - width);
    parts_[2] = text.substr(second + width);
    key_ = key;
    ++built_;
  }
  const std::string seq = std::to_string(++seq_);
  const std::string time = std::to_string(in.time_ms);
  std::string out;
  out.reserve(parts_[0].size() + parts_[1].size() + parts_[2].size() + 40);
  out += parts_[0];
  out += time_first_ ? time : seq;
  out += parts_[1];
  out += time_first_ ? seq : time;
  out += parts_[2];
  return out;
}

}  // namespace mcemu::web::api
