// The RefGo command table's vocabulary (refgo.md §6): one row per command word with its argument
// shape and handler, and the outcome a handler returns. The table itself is command_table.cpp;
// the handlers live in commands_*.cpp, grouped by topic.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "drive/od/abort_code.hpp"
#include "protocols/refgo/codec.hpp"

namespace mcemu::refgo {

class Interpreter;

// What a handler did. The interpreter turns it into the reply bytes (reply.hpp).
struct Outcome {
  enum class Kind : std::uint8_t { done, answer, error, pending };
  Kind kind = Kind::done;
  std::string text;  // answer: the answer line; error: the prefix (empty = trimmed echo)
  od::AbortCode code = od::AbortCode::none;

  static Outcome ok() { return {}; }
  static Outcome answer(std::string line) { return {Kind::answer, std::move(line), od::AbortCode::none}; }
  static Outcome error(od::AbortCode c, std::string prefix = {}) { return {Kind::error, std::move(prefix), c}; }
  static Outcome pending() { return {Kind::pending, {}, od::AbortCode::none}; }
  // none → ok, anything else → error with the given prefix.
  static Outcome from(od::AbortCode c, std::string prefix = {}) {
    return c == od::AbortCode::none ? ok() : error(c, std::move(prefix));
  }
};

// Argument shapes of refgo.md §6 / §4.5.
enum class ArgShape : std::uint8_t {
  none,          // no argument text allowed (08000000h otherwise)
  optional_int,  // [<n>]
  required_int,  // <n>
  objects,       // OR/OW tokens, parsed by the handler (§9)
};

struct IntRange {
  std::int64_t min;
  std::int64_t max;
};
inline constexpr IntRange k_any{-9999999999LL, 9999999999LL};  // no range of its own (REF: the OD checks)
inline constexpr IntRange k_i32{-2147483648LL, 2147483647LL};
inline constexpr IntRange k_u32{0, 4294967295LL};

// One line being executed. A handler that may return pending takes completion(): it delivers the
// final outcome as the line's late reply. Built on demand (a copy of the line and of the caller's
// reply function), so the commands that never go pending allocate nothing for it.
struct Call {
  const Lexed& line;
  std::optional<std::int64_t> arg;  // the integer argument, when the shape has one and it was given
  const std::function<void(std::string reply)>* late = nullptr;  // the caller's; may be null or empty
  std::function<void(const Outcome&)> completion() const;        // defined in interpreter.cpp
};

using Handler = Outcome (*)(Interpreter&, const Call&);

struct CommandRow {
  std::string_view word;
  ArgShape shape;
  IntRange range;
  Handler handler;
};

// The table of refgo.md §6; lookup by exact (upper-case) command word.
std::span<const CommandRow> command_table();
const CommandRow* find_command(std::string_view word);

}  // namespace mcemu::refgo
