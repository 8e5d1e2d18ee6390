#include "scripting/core/calls.hpp"

#include <array>
#include <memory>

#include "drive/od/abort_code.hpp"
#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/reply.hpp"

namespace mcemu::scripting {

namespace h = core::helpers;
using ipc::Value;

namespace {

std::int64_t num(std::span<const Value> args, std::size_t k, std::int64_t fallback = 0) {
  return k < args.size() ? args[k].i : fallback;
}

Values none() { return {Value::none()}; }
Values integer(std::int64_t v) { return {Value::integer(v)}; }

std::string hex4(std::uint32_t v, int digits) {
  static constexpr char k_hex[] = "0123456789ABCDEF";
  std::string s(static_cast<std::size_t>(digits), '0');
  for (int i = 0; i < digits; ++i) s[static_cast<std::size_t>(digits - 1 - i)] = k_hex[(v >> (4 * i)) & 0xF];
  return s;
}

// One write inside a helper: a refusal is skipped and traced (§5.3).
void put(CallContext& c, std::string_view fn, std::uint16_t index, std::uint8_t sub, std::int64_t value) {
  const auto code = c.drive.od.write(index, sub, od::Value{value}, c.drive.origin);
  if (code != od::AbortCode::none && code != od::AbortCode::pending && c.refused) {
    c.refused(std::string(fn) + ": " + hex4(index, 4) + "h." + hex4(sub, 2) + " := " + std::to_string(value) +
              " refused, " + hex4(od::to_u32(code), 8) + "h");
  }
}

std::int64_t get(CallContext& c, std::uint16_t index, std::uint8_t sub = 0) {
  auto r = c.drive.od.read_number(index, sub);
  return r.ok() ? *r : 0;
}

void stopgen(CallContext& c) { c.refgo.programs().stop_all(); }

// ---- mcdrive (scripting.md §5.5)

std::optional<Values> write_object(CallContext& c, std::span<const Value> a, Later&) {
  return integer(static_cast<std::uint32_t>(h::write_object(c.drive, static_cast<std::uint16_t>(num(a, 0)),
                                                            static_cast<std::uint8_t>(num(a, 1)), num(a, 2))));
}
std::optional<Values> read_object(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t i = num(a, 0);
  const std::int64_t s = num(a, 1);
  // Index and sub-index outside their types name no object (the OD would see a truncated address).
  if (i < 0 || i > 0xFFFF) return integer(static_cast<std::int32_t>(od::to_u32(od::AbortCode::no_object)));
  if (s < 0 || s > 0xFF) return integer(static_cast<std::int32_t>(od::to_u32(od::AbortCode::no_sub)));
  return integer(h::read_object(c.drive, static_cast<std::uint16_t>(i), static_cast<std::uint8_t>(s)));
}
std::optional<Values> write_control(CallContext& c, std::span<const Value> a, Later&) {
  put(c, "WriteControl", 0x6040, 0, num(a, 0));
  return none();
}
std::optional<Values> read_statusword(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::read_statusword(c.drive));
}
std::optional<Values> enable_drive(CallContext& c, std::span<const Value>, Later&) {
  stopgen(c);
  return integer(h::enable_drive(c.drive) ? 1 : 0);
}
std::optional<Values> power_quit(CallContext& c, std::span<const Value>, Later&) {
  stopgen(c);
  h::power_quit(c.drive);
  return none();
}
std::optional<Values> stop_motion(CallContext& c, std::span<const Value>, Later&) {
  stopgen(c);
  h::stop_motion(c.drive);
  return none();
}
std::optional<Values> continue_motion(CallContext& c, std::span<const Value>, Later&) {
  h::continue_motion(c.drive);
  return none();
}
// Store/Restore answer when the file is durable (persistence.md §12); an accepted factory reset
// stops this script before the answer, so that call never returns (scripting.md §5.5).
std::optional<Values> store_permanent(CallContext& c, std::span<const Value>, Later& later) {
  auto shared = std::make_shared<Later>(std::move(later));
  const auto code = h::store_permanent(c.drive, [shared](od::AbortCode) { (*shared)(none()); });
  if (code == od::AbortCode::pending) return std::nullopt;
  return none();
}
std::optional<Values> reset_to_factory(CallContext& c, std::span<const Value>, Later& later) {
  auto shared = std::make_shared<Later>(std::move(later));
  const auto code = h::reset_to_factory(c.drive, [shared](od::AbortCode) { (*shared)(none()); });
  if (code == od::AbortCode::pending) return std::nullopt;
  return none();
}
std::optional<Values> go_pos_abs(CallContext& c, std::span<const Value> a, Later&) {
  stopgen(c);
  h::go_pos_abs(c.drive, static_cast<std::int32_t>(num(a, 0)));
  return none();
}
std::optional<Values> go_pos_rel(CallContext& c, std::span<const Value> a, Later&) {
  stopgen(c);
  h::go_pos_rel(c.drive, static_cast<std::int32_t>(num(a, 0)));
  return none();
}
std::optional<Values> go_vel(CallContext& c, std::span<const Value> a, Later&) {
  stopgen(c);
  h::go_vel(c.drive, static_cast<std::int32_t>(num(a, 0)));
  return none();
}
std::optional<Values> go_home(CallContext& c, std::span<const Value> a, Later&) {
  stopgen(c);
  // The parameter writes of GoHome one by one, a refused one skipped (§5.3: e.g. Fullmo's
  // GoHome(35, 0, 0, 0), whose 609Ah := 0 the OD refuses); then the helper with the values now in
  // force, so that its own writes change nothing. A refused method (6098h is i8) ends the call.
  if (c.drive.od.write(0x6098, 0, od::Value{num(a, 0)}, c.drive.origin) != od::AbortCode::none) {
    put(c, "GoHome", 0x6098, 0, num(a, 0));
    return none();
  }
  put(c, "GoHome", 0x6099, 1, num(a, 1));
  put(c, "GoHome", 0x609A, 0, num(a, 2));
  put(c, "GoHome", 0x607C, 0, num(a, 3));
  const auto result =
      h::go_home(c.drive, static_cast<std::int8_t>(num(a, 0)), static_cast<std::uint32_t>(get(c, 0x6099, 1)),
                 static_cast<std::uint32_t>(get(c, 0x609A)), static_cast<std::int32_t>(get(c, 0x607C)));
  // A write of the helper itself refused (e.g. 6060h := 6): named like the parameter writes above.
  if (result.refused && c.refused) c.refused("GoHome: " + h::describe(result));
  return none();
}

template <std::uint16_t Index, const char* Name>
std::optional<Values> setter(CallContext& c, std::span<const Value> a, Later&) {
  put(c, Name, Index, 0, num(a, 0));
  return none();
}
constexpr char k_set_target_pos[] = "SetTargetPos";
constexpr char k_set_pos_vel[] = "SetPosVel";
constexpr char k_set_acc[] = "SetAcc";
constexpr char k_set_dec[] = "SetDec";
constexpr char k_set_op_mode[] = "SetOpMode";
constexpr char k_set_torque[] = "SetTorque";

std::optional<Values> get_op_mode(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::get_op_mode(c.drive));
}
std::optional<Values> get_actual_pos(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::get_actual_pos(c.drive));
}
std::optional<Values> chk_in(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t n = num(a, 0);
  if (n < 1 || n > 10) return integer(0);
  return integer((get(c, 0x60FD) >> (15 + n)) & 1);
}
std::optional<Values> set_out(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t n = num(a, 0);
  if (n >= 1 && n <= 4) put(c, "SetOut", 0x60FE, 1, get(c, 0x60FE, 1) | (std::int64_t{1} << (15 + n)));
  return none();
}
std::optional<Values> clear_out(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t n = num(a, 0);
  if (n >= 1 && n <= 4) put(c, "ClearOut", 0x60FE, 1, get(c, 0x60FE, 1) & ~(std::int64_t{1} << (15 + n)));
  return none();
}
std::optional<Values> chk_ready(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::chk_ready(c.drive) ? 1 : 0);
}
std::optional<Values> chk_enabled(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::chk_enabled(c.drive) ? 1 : 0);
}
std::optional<Values> chk_moving(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::chk_moving(c.drive) ? 1 : 0);
}
std::optional<Values> chk_error(CallContext& c, std::span<const Value>, Later&) {
  return integer(h::chk_error(c.drive) ? 1 : 0);
}
std::optional<Values> chk_mfr_status(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t b = num(a, 0);
  return integer(b >= 0 && b < 32 && h::chk_mfr_status(c.drive, static_cast<int>(b)) ? 1 : 0);
}
std::optional<Values> send_emcy_msg(CallContext& c, std::span<const Value> a, Later&) {
  h::send_emcy_msg(c.drive, static_cast<std::uint32_t>(num(a, 0)), static_cast<std::uint8_t>(num(a, 1, 0) & 0xFF),
                   static_cast<std::uint16_t>(num(a, 2, 0x509B) & 0xFFFF));
  return none();
}

// ---- refgo (scripting.md §6)

std::optional<Values> refgo_cmd(CallContext& c, std::span<const Value> a, Later& later) {
  std::string line = a.empty() ? std::string() : a[0].s;
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  // The same byte filter as a TCP line (refgo.md §2.3), then the built-in interpreter only (§5.5).
  std::string filtered;
  for (const char ch : line) {
    const int b = refgo::filter_byte(static_cast<unsigned char>(ch));
    if (b >= 0) filtered += static_cast<char>(b);
  }
  if (filtered.size() > refgo::k_max_line) return none();
  auto shared = std::make_shared<Later>(std::move(later));
  auto reply = c.refgo.execute(filtered,
                               [shared, filtered](std::string late) { (*shared)({refgo_cmd_result(filtered, late)}); });
  if (!reply) return std::nullopt;
  return Values{refgo_cmd_result(filtered, *reply)};
}
std::optional<Values> refgo_open(CallContext& c, std::span<const Value> a, Later&) {
  const std::int64_t mode = num(a, 0);
  if (mode < 1 || mode > 3) return integer(-1);
  c.refgo.attachment().open(static_cast<refgo::AttachMode>(mode));
  return integer(0);
}
std::optional<Values> refgo_read(CallContext& c, std::span<const Value>, Later&) {
  auto line = c.refgo.attachment().read();
  if (!line) return none();
  return Values{Value::bytes(std::move(*line))};
}
std::optional<Values> refgo_write(CallContext& c, std::span<const Value> a, Later&) {
  if (a.empty()) return integer(-1);
  return integer(c.refgo.attachment().write(a[0].s) ? 0 : -1);
}
std::optional<Values> refgo_close(CallContext& c, std::span<const Value>, Later&) {
  c.refgo.attachment().close();
  return none();
}

// clang-format off
constexpr std::array k_table{
    FunctionRow{1, "mcdrive", "WriteObject", "iii", 3, write_object},
    FunctionRow{2, "mcdrive", "ReadObject", "ii", 2, read_object},
    FunctionRow{3, "mcdrive", "WriteControl", "i", 1, write_control},
    FunctionRow{4, "mcdrive", "ReadStatusword", "", 0, read_statusword},
    FunctionRow{5, "mcdrive", "EnableDrive", "", 0, enable_drive},
    FunctionRow{6, "mcdrive", "PowerQuit", "", 0, power_quit},
    FunctionRow{7, "mcdrive", "StopMotion", "", 0, stop_motion},
    FunctionRow{8, "mcdrive", "ContinueMotion", "", 0, continue_motion},
    FunctionRow{9, "mcdrive", "StorePermanent", "", 0, store_permanent},
    FunctionRow{10, "mcdrive", "ResetToFactory", "", 0, reset_to_factory},
    FunctionRow{11, "mcdrive", "GoPosAbs", "i", 1, go_pos_abs},
    FunctionRow{12, "mcdrive", "GoPosRel", "i", 1, go_pos_rel},
    FunctionRow{13, "mcdrive", "GoVel", "i", 1, go_vel},
    FunctionRow{14, "mcdrive", "GoHome", "iiii", 4, go_home},
    FunctionRow{15, "mcdrive", "SetTargetPos", "i", 1, setter<0x607A, k_set_target_pos>},
    FunctionRow{16, "mcdrive", "SetPosVel", "i", 1, setter<0x6081, k_set_pos_vel>},
    FunctionRow{17, "mcdrive", "SetAcc", "i", 1, setter<0x6083, k_set_acc>},
    FunctionRow{18, "mcdrive", "SetDec", "i", 1, setter<0x6084, k_set_dec>},
    FunctionRow{19, "mcdrive", "SetOpMode", "i", 1, setter<0x6060, k_set_op_mode>},
    FunctionRow{20, "mcdrive", "GetOpMode", "", 0, get_op_mode},
    FunctionRow{21, "mcdrive", "SetTorque", "i", 1, setter<0x6073, k_set_torque>},
    FunctionRow{22, "mcdrive", "ChkIn", "i", 1, chk_in},
    FunctionRow{23, "mcdrive", "SetOut", "i", 1, set_out},
    FunctionRow{24, "mcdrive", "ClearOut", "i", 1, clear_out},
    FunctionRow{25, "mcdrive", "GetActualPos", "", 0, get_actual_pos},
    FunctionRow{26, "mcdrive", "ChkReady", "", 0, chk_ready},
    FunctionRow{27, "mcdrive", "ChkEnabled", "", 0, chk_enabled},
    FunctionRow{28, "mcdrive", "ChkMoving", "", 0, chk_moving},
    FunctionRow{29, "mcdrive", "ChkError", "", 0, chk_error},
    FunctionRow{30, "mcdrive", "ChkMfrStatus", "i", 1, chk_mfr_status},
    FunctionRow{31, "mcdrive", "SendEmcyMsg", "iii", 1, send_emcy_msg},
    FunctionRow{40, "refgo", "cmd", "s", 1, refgo_cmd},
    FunctionRow{41, "refgo", "open", "i", 1, refgo_open},
    FunctionRow{42, "refgo", "read", "", 0, refgo_read},
    FunctionRow{43, "refgo", "write", "b", 1, refgo_write},
    FunctionRow{44, "refgo", "close", "", 0, refgo_close},
};
// clang-format on

bool arg_ok(char shape, const Value& v) {
  switch (shape) {
    case 'i': return v.tag == Value::Tag::integer && v.i >= -2147483648LL && v.i <= 2147483647LL;
    case 's': return v.tag == Value::Tag::text;
    case 'b': return v.tag == Value::Tag::text || v.tag == Value::Tag::bytes;
    default: return false;
  }
}

// The answer line of a RefGo reply "<echo>\r\n<answer>\r\n>", if any.
std::optional<std::string_view> answer_line(std::string_view reply) {
  const auto first = reply.find("\r\n");
  if (first == std::string_view::npos) return std::nullopt;
  const std::string_view rest = reply.substr(first + 2);
  const auto second = rest.find("\r\n");
  if (second == std::string_view::npos) return std::nullopt;
  return rest.substr(0, second);
}

std::optional<std::int64_t> parse_integer(std::string_view s, int base) {
  if (s.empty()) return std::nullopt;
  bool negative = false;
  std::size_t i = 0;
  if (base == 10 && (s[0] == '-' || s[0] == '+')) {
    negative = s[0] == '-';
    i = 1;
  }
  if (i >= s.size() || s.size() - i > 16) return std::nullopt;
  std::int64_t v = 0;
  for (; i < s.size(); ++i) {
    const char ch = s[i];
    int d = -1;
    if (ch >= '0' && ch <= '9') d = ch - '0';
    if (base == 16 && ch >= 'a' && ch <= 'f') d = ch - 'a' + 10;
    if (base == 16 && ch >= 'A' && ch <= 'F') d = ch - 'A' + 10;
    if (d < 0 || d >= base) return std::nullopt;
    v = v * base + d;
  }
  return negative ? -v : v;
}

}  // namespace

std::span<const FunctionRow> function_table() { return k_table; }

const FunctionRow* find_function(std::uint16_t id) {
  for (const auto& row : k_table) {
    if (row.id == id) return &row;
  }
  return nullptr;
}

std::optional<Values> execute_call(CallContext& ctx, const ipc::Call& call, Later later, bool& malformed) {
  malformed = false;
  const FunctionRow* row = find_function(call.function);
  if (row == nullptr || call.args.size() < row->required || call.args.size() > row->args.size()) {
    malformed = true;
    return std::nullopt;
  }
  for (std::size_t k = 0; k < call.args.size(); ++k) {
    if (!arg_ok(row->args[k], call.args[k])) {
      malformed = true;
      return std::nullopt;
    }
  }
  return row->handler(ctx, call.args, later);
}

ipc::Value refgo_cmd_result(std::string_view line, std::string_view reply) {
  const refgo::Lexed lexed = refgo::lex(line);
  if (reply == refgo::k_prompt) return Value::none();  // empty or unknown line
  const auto answer = answer_line(reply);
  if (!answer) return Value::text("");
  if (answer->find(",ERROR,") != std::string_view::npos) return Value::none();
  const std::string_view word = lexed.word();
  if (word == "TS" || word == "TP" || word == "TPSR") {
    if (auto v = parse_integer(*answer, word == "TPSR" ? 16 : 10)) return Value::integer(*v);
    return Value::none();
  }
  return Value::text(std::string(*answer));
}

Values table_values() {
  Values out;
  for (const auto& row : k_table) {
    out.push_back(Value::integer(row.id));
    out.push_back(Value::text(std::string(row.module)));
    out.push_back(Value::text(std::string(row.name)));
    out.push_back(Value::text(std::string(row.args)));
    out.push_back(Value::integer(row.required));
  }
  return out;
}

}  // namespace mcemu::scripting
