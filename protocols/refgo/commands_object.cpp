// OR and OW (refgo.md §9): object access through the OD's value interface, with the abort code of
// any failure in the error reply.
#include <string>

#include "protocols/refgo/commands.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo::cmd {

namespace {

// Upper-cased request text from the command word to `args_len` bytes into the arguments.
std::string prefix_of(const Lexed& line, std::size_t args_len) {
  return line.echo.substr(line.word_pos, line.word_len + args_len);
}

// Index above FFFFh / sub-index above FFh (refgo.md §9.1).
od::AbortCode address_check(std::uint32_t index, std::uint32_t sub) {
  if (index > 0xFFFF) return od::AbortCode::no_object;
  if (sub > 0xFF) return od::AbortCode::no_sub;
  return od::AbortCode::none;
}

std::string format_value(const od::Value& v, bool hex) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  const std::int64_t n = std::get<std::int64_t>(v);
  return hex ? hex_h(static_cast<std::uint32_t>(n)) : std::to_string(n);
}

}  // namespace

Outcome object_read(Interpreter& in, const Call& c) {
  const auto r = parse_read_args(c.line.args());
  if (!r) return Outcome::error(od::AbortCode::general);
  std::string prefix = prefix_of(c.line, r->prefix_len);
  if (const auto bad = address_check(r->index, r->sub); bad != od::AbortCode::none) {
    return Outcome::error(bad, std::move(prefix));
  }
  const auto v = in.od().read(static_cast<std::uint16_t>(r->index), static_cast<std::uint8_t>(r->sub));
  if (!v) return Outcome::error(v.error(), std::move(prefix));
  return Outcome::answer(prefix + "," + format_value(*v, r->hex));
}

Outcome object_write(Interpreter& in, const Call& c) {
  const auto w = parse_write_args(c.line.args());
  if (!w) return Outcome::error(od::AbortCode::general);
  std::string prefix = prefix_of(c.line, w->prefix_len);
  if (const auto bad = address_check(w->index, w->sub); bad != od::AbortCode::none) {
    return Outcome::error(bad, std::move(prefix));
  }
  const auto result = [prefix](od::AbortCode code) {
    return code == od::AbortCode::none ? Outcome::answer(prefix + ",OK") : Outcome::error(code, prefix);
  };
  // Store/Restore answer `pending` and complete when the file is durable (refgo.md §2.5).
  const auto code = in.od().write(
      static_cast<std::uint16_t>(w->index), static_cast<std::uint8_t>(w->sub), od::Value{w->value}, od::Origin::refgo,
      [later = c.completion(), result](od::AbortCode final_code) { later(result(final_code)); });
  if (code == od::AbortCode::pending) return Outcome::pending();
  return result(code);
}

}  // namespace mcemu::refgo::cmd
