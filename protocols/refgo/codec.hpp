// The RefGo lexical layer (refgo.md §2.3, §2.4, §4, §9.1): the byte filter for the shared line
// assembler, the upper-cased echo with its command word, the integer argument and the OR/OW tokens.
//
// Contract: pure functions on already framed lines (protocols/line/line_assembler.hpp does the
// framing). Nothing here throws or allocates beyond the returned strings; every input, including
// binary garbage, yields a value (an empty command word, "absent" or "malformed").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace mcemu::refgo {

// Maximum request length after control bytes are removed (refgo.md §2.4).
inline constexpr std::size_t k_max_line = 255;

// The RefGo byte filter (refgo.md §2.3): TAB becomes a space, the other control bytes 0x00–0x1F and
// 0x7F are dropped, everything else (0x80–0xFF too) is kept. Never called for CR/LF.
int filter_byte(unsigned char c);

// A request line after upper-casing (refgo.md §3.1, §4.3). Positions index into `echo`.
struct Lexed {
  std::string echo;          // the line with ASCII a–z turned into A–Z, nothing else changed
  std::size_t word_pos = 0;  // first byte that is not a space
  std::size_t word_len = 0;  // maximal run of letters A–Z from word_pos (0: empty command word)
  std::size_t trim_end = 0;  // one past the last byte that is not a space

  std::string_view word() const { return std::string_view(echo).substr(word_pos, word_len); }
  // Everything after the command word (trailing spaces included).
  std::string_view args() const { return std::string_view(echo).substr(word_pos + word_len); }
  // The echo without leading and trailing spaces: the prefix of error replies (refgo.md §10).
  std::string_view trimmed() const { return std::string_view(echo).substr(word_pos, trim_end - word_pos); }
  // Empty or spaces only (refgo.md §3.2).
  bool blank() const { return trim_end <= word_pos; }
};

Lexed lex(std::string_view line);

// Integer argument of refgo.md §4.5: optional spaces, an optional sign directly followed by 1–10
// decimal digits, then only spaces.
enum class ArgStatus : std::uint8_t { absent, ok, malformed };
struct IntArg {
  ArgStatus status = ArgStatus::absent;
  std::int64_t value = 0;
};
IntArg parse_int_arg(std::string_view args);
// True if `args` holds spaces only (commands without an argument, refgo.md §6).
bool no_argument(std::string_view args);

// OR/OW arguments (refgo.md §9.1), parsed from Lexed::args() (upper case). Index and sub-index are
// 1–8 hex digits with an optional H; the caller range-checks them (above FFFFh / FFh).
// `prefix_len` = length of the args text up to the end of the sub-index token (OR) or of the value
// token (OW), so that word + args.substr(0, prefix_len) is the answer prefix of §9.3.
struct ReadArgs {
  std::uint32_t index = 0;
  std::uint32_t sub = 0;
  bool hex = false;  // ",h" option
  std::size_t prefix_len = 0;
};
struct WriteArgs {
  std::uint32_t index = 0;
  std::uint32_t sub = 0;
  std::int64_t value = 0;
  std::size_t prefix_len = 0;
};
std::optional<ReadArgs> parse_read_args(std::string_view args);
std::optional<WriteArgs> parse_write_args(std::string_view args);

// The value token of OW: decimal with optional sign, hex with an H suffix or a 0X prefix (no sign);
// nullopt if malformed or outside the int64 range.
std::optional<std::int64_t> parse_value(std::string_view token);

}  // namespace mcemu::refgo
