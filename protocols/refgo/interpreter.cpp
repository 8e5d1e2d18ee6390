#include "protocols/refgo/interpreter.hpp"

#include <memory>

#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo {

namespace {

// The reply bytes of a finished outcome (refgo.md §3.1, §10).
std::string format(const Lexed& line, const Outcome& o) {
  switch (o.kind) {
    case Outcome::Kind::answer: return reply(line.echo, o.text);
    case Outcome::Kind::error: return error_reply(line.echo, o.text.empty() ? line.trimmed() : o.text, o.code);
    case Outcome::Kind::done:
    case Outcome::Kind::pending: break;
  }
  return reply(line.echo);
}

// Validates the argument text against the command's shape (refgo.md §4.5, §6). Returns the
// integer (if any) or the error outcome.
std::optional<Outcome> check_argument(const CommandRow& row, const Lexed& line, std::optional<std::int64_t>& arg) {
  const std::string_view args = line.args();
  switch (row.shape) {
    case ArgShape::objects: return std::nullopt;
    case ArgShape::none:
      if (!no_argument(args)) return Outcome::error(od::AbortCode::general);
      return std::nullopt;
    case ArgShape::optional_int:
    case ArgShape::required_int: {
      const IntArg a = parse_int_arg(args);
      if (a.status == ArgStatus::malformed) return Outcome::error(od::AbortCode::general);
      if (a.status == ArgStatus::absent) {
        if (row.shape == ArgShape::required_int) return Outcome::error(od::AbortCode::general);
        return std::nullopt;
      }
      if (a.value < row.range.min || a.value > row.range.max) return Outcome::error(od::AbortCode::invalid_value);
      arg = a.value;
      return std::nullopt;
    }
  }
  return std::nullopt;
}

}  // namespace

Interpreter::Interpreter(od::ObjectDictionary& od, core::DriveCore& core)
    : od_(od), core_(core), programs_({core, od, od::Origin::refgo}) {
  // A master's write of a motion object ends a running program (the program's own writes do not).
  od_.on_change({{0x6040, 0}, {0x6060, 0}, {0x60FF, 0}}, [this](const od::EntryInfo&, const od::Value&) {
    if (!programs_.own_write()) programs_.stop_all();
  });
}

void Interpreter::reset() {
  vars_ = Variables{};
  programs_.stop_all();
}

std::function<void(const Outcome&)> Call::completion() const {
  if (late == nullptr || !*late) return [](const Outcome&) {};
  // the completion may run after the line is gone: it keeps its own copy
  return [line = line, late = *late](const Outcome& o) { late(format(line, o)); };
}

std::optional<std::string> Interpreter::execute(std::string_view text, const Later& later) {
  const Lexed line = lex(text);
  if (line.blank()) return std::string(k_prompt);
  const CommandRow* row = find_command(line.word());
  if (row == nullptr) return std::string(k_prompt);

  std::optional<std::int64_t> arg;
  if (auto bad = check_argument(*row, line, arg)) return format(line, *bad);

  const Call call{line, arg, &later};
  const Outcome o = row->handler(*this, call);
  if (o.kind == Outcome::Kind::pending) return std::nullopt;
  return format(line, o);
}

}  // namespace mcemu::refgo
