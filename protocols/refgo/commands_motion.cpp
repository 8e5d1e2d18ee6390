// Motion and power commands (refgo.md §7.1–§7.7): G, GW, SM, CM, PWC, PQ, REF, JP, JN, RR. Each is
// STOPGEN followed by the core's helpers (drive-core.md §12); nothing here drives the state
// machine by itself. A command that is valid but cannot act now (AUTOENABLE did not reach OE, a
// fault) answers echo + ">" (§10); a refused object write answers its abort code.
#include <algorithm>
#include <limits>

#include "protocols/refgo/commands.hpp"
#include "protocols/refgo/interpreter.hpp"

namespace mcemu::refgo::cmd {

namespace {

namespace helpers = core::helpers;

// device_state from a Go… helper means "AUTOENABLE did not reach OE": no motion, no error.
Outcome motion_result(od::AbortCode c) { return c == od::AbortCode::device_state ? Outcome::ok() : Outcome::from(c); }

std::int64_t read(Interpreter& in, std::uint16_t index, std::uint8_t sub = 0) {
  const auto r = in.od().read_number(index, sub);
  return r ? *r : 0;
}

std::int32_t saturate_i32(std::int64_t v) {
  return static_cast<std::int32_t>(
      std::clamp<std::int64_t>(v, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max()));
}

// G / GW: STOPGEN, then the GoPos… helper with the target argument, or with the 607Ah set by
// PO / WA (§7.2). The helper writes 607Ah even when AUTOENABLE fails.
Outcome go(Interpreter& in, const Call& c, bool relative) {
  in.programs().stop_all();
  const auto d = in.drive();
  const auto target = static_cast<std::int32_t>(c.arg ? *c.arg : read(in, 0x607A));
  return motion_result(relative ? helpers::go_pos_rel(d, target) : helpers::go_pos_abs(d, target));
}

Outcome jog(Interpreter& in, const Call& c, bool positive) {
  in.programs().stop_all();
  const auto d = in.drive();
  const std::int64_t speed = read(in, 0x6081);
  const auto code = helpers::go_vel(d, saturate_i32(positive ? speed : -speed));
  if (code == od::AbortCode::none) in.programs().arm_jog(static_cast<std::uint32_t>(c.arg.value_or(0)));
  return motion_result(code);
}

}  // namespace

Outcome go_absolute(Interpreter& in, const Call& c) { return go(in, c, false); }
Outcome go_relative(Interpreter& in, const Call& c) { return go(in, c, true); }

Outcome stop_motion(Interpreter& in, const Call&) {
  in.programs().stop_all();
  helpers::stop_motion(in.drive());
  return Outcome::ok();
}

Outcome continue_motion(Interpreter& in, const Call&) {
  helpers::continue_motion(in.drive());
  return Outcome::ok();
}

// PWC (§7.4): SETMODE 1, then EnableDrive (which resets a fault first).
Outcome power_continue(Interpreter& in, const Call&) {
  in.programs().stop_all();
  const auto d = in.drive();
  if (read(in, 0x6061) != 1 || read(in, 0x6060) != 1) {
    if (const auto code = helpers::set_op_mode(d, 1); code != od::AbortCode::none) return Outcome::error(code);
    d.core.apply_mode_switch_now();
  }
  helpers::enable_drive(d);
  return Outcome::ok();
}

Outcome power_quit(Interpreter& in, const Call&) {
  in.programs().stop_all();
  helpers::power_quit(in.drive());
  return Outcome::ok();
}

// REF<n> (§7.5): homing with method n and the current homing parameters; REF alone does nothing.
Outcome home(Interpreter& in, const Call& c) {
  if (!c.arg) return Outcome::ok();
  in.programs().stop_all();
  const auto d = in.drive();
  // 6098h is i8: the OD's range check answers 06090031h / 06090032h for other values.
  if (const auto code = in.od().write(0x6098, 0, od::Value{*c.arg}, d.origin); code != od::AbortCode::none) {
    return Outcome::error(code);
  }
  return motion_result(
      helpers::go_home(d, static_cast<std::int8_t>(*c.arg), static_cast<std::uint32_t>(read(in, 0x6099, 1)),
                       static_cast<std::uint32_t>(read(in, 0x609A)), static_cast<std::int32_t>(read(in, 0x607C)))
          .code);
}

Outcome jog_positive(Interpreter& in, const Call& c) { return jog(in, c, true); }
Outcome jog_negative(Interpreter& in, const Call& c) { return jog(in, c, false); }

// RR[<n>] (§7.7): Back & Forth between the last target and last target + repeat way.
Outcome back_and_forth(Interpreter& in, const Call& c) {
  if (c.arg) in.variables().repeat_way = *c.arg;
  in.programs().stop_all();
  const std::int64_t way = in.variables().repeat_way;
  if (way == 0) return Outcome::ok();
  const auto d = in.drive();
  const std::int64_t base = in.programs().back_and_forth_base();
  if (read(in, 0x6061) != 1 || read(in, 0x6060) != 1) {
    if (const auto code = helpers::set_op_mode(d, 1); code != od::AbortCode::none) return Outcome::error(code);
    d.core.apply_mode_switch_now();
  }
  if (!helpers::autoenable(d)) return Outcome::ok();
  return motion_result(in.programs().start_back_and_forth(base, way, in.variables().wait_time_ms));
}

}  // namespace mcemu::refgo::cmd
