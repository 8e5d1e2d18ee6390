// TP, TPSR, TS, TI (refgo.md §8): answers computed from 6064h, 6041h and 60FDh.
#include <string>

#include "protocols/refgo/commands.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/reply.hpp"
#include "protocols/refgo/status.hpp"

namespace mcemu::refgo::cmd {

namespace {

od::Result<std::uint32_t> read_tpsr(Interpreter& in) {
  const auto sw = in.od().read_number(0x6041, 0);
  if (!sw) return sw.error();
  return tpsr(static_cast<std::uint16_t>(*sw));
}

}  // namespace

Outcome tell_position(Interpreter& in, const Call&) {
  const auto p = in.od().read_number(0x6064, 0);
  if (!p) return Outcome::error(p.error());
  return Outcome::answer(std::to_string(*p));
}

Outcome tell_tpsr(Interpreter& in, const Call&) {
  const auto t = read_tpsr(in);
  if (!t) return Outcome::error(t.error());
  return Outcome::answer(hex8(*t));
}

Outcome tell_status(Interpreter& in, const Call&) {
  const auto t = read_tpsr(in);
  if (!t) return Outcome::error(t.error());
  return Outcome::answer(std::to_string(simple_status(*t)));
}

Outcome tell_input(Interpreter& in, const Call& c) {
  const auto inputs = in.od().read_number(0x60FD, 0);
  if (!inputs) return Outcome::error(inputs.error());
  const auto v = static_cast<std::uint32_t>(*inputs);
  if (c.arg) return Outcome::answer(refgo::tell_input(v, static_cast<int>(*c.arg)));
  return Outcome::answer(tell_inputs(v));
}

}  // namespace mcemu::refgo::cmd
