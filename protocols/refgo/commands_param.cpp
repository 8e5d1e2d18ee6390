// Parameter commands (refgo.md §7.2, §7.6–§7.8): single object writes, the digital outputs and the
// interpreter variables. None of them starts or stops motion.
#include <algorithm>
#include <limits>

#include "protocols/refgo/commands.hpp"
#include "protocols/refgo/interpreter.hpp"

namespace mcemu::refgo::cmd {

namespace {

Outcome write(Interpreter& in, std::uint16_t index, std::uint8_t sub, std::int64_t v) {
  return Outcome::from(in.od().write(index, sub, od::Value{v}, od::Origin::refgo));
}

// SO/CO: read-modify-write of bit (15 + n) of 60FEh.01 (refgo.md §7.8).
Outcome change_output(Interpreter& in, const Call& c, bool on) {
  const auto current = in.od().read_number(0x60FE, 1);
  if (!current) return Outcome::error(current.error());
  const std::uint32_t bit = 1U << (15 + *c.arg);
  auto v = static_cast<std::uint32_t>(*current);
  v = on ? (v | bit) : (v & ~bit);
  return write(in, 0x60FE, 1, v);
}

}  // namespace

Outcome speed(Interpreter& in, const Call& c) {
  const std::int64_t n = *c.arg;
  if (auto o = write(in, 0x6081, 0, n); o.kind != Outcome::Kind::done) return o;
  // A running jog follows the new speed; SP never starts motion (refgo.md §7.6).
  const auto mode = in.od().read_number(0x6061, 0);
  const auto vel = in.od().read_number(0x60FF, 0);
  if (!mode || !vel || *mode != 3 || *vel == 0) return Outcome::ok();
  const std::int64_t signed_speed = *vel > 0 ? n : -n;
  const std::int64_t saturated = std::clamp<std::int64_t>(signed_speed, std::numeric_limits<std::int32_t>::min(),
                                                          std::numeric_limits<std::int32_t>::max());
  // Changing the speed of a running jog is not a new motion command: the jog timer stays armed.
  Programs::OwnWrites own(in.programs());
  return write(in, 0x60FF, 0, saturated);
}

Outcome acceleration(Interpreter& in, const Call& c) { return write(in, 0x6083, 0, *c.arg); }
Outcome deceleration(Interpreter& in, const Call& c) { return write(in, 0x6084, 0, *c.arg); }
Outcome jerk(Interpreter& in, const Call& c) { return write(in, 0x60A4, 0, *c.arg); }
Outcome target(Interpreter& in, const Call& c) { return write(in, 0x607A, 0, *c.arg); }
Outcome set_output(Interpreter& in, const Call& c) { return change_output(in, c, true); }
Outcome clear_output(Interpreter& in, const Call& c) { return change_output(in, c, false); }

Outcome repeat_way(Interpreter& in, const Call& c) {
  in.variables().repeat_way = *c.arg;
  return Outcome::ok();
}

Outcome wait_time(Interpreter& in, const Call& c) {
  in.variables().wait_time_ms = static_cast<std::uint32_t>(*c.arg);
  return Outcome::ok();
}

}  // namespace mcemu::refgo::cmd
