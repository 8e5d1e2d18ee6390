// The lexical rules of MC BASIC (faulhaber.md §9.2): splitting a program into lines (CR, LF or
// CR LF) and one line into tokens. `'` starts a comment; keywords are case-insensitive; numbers are
// decimal or `$` hexadecimal (taken modulo 2^32); `$IIII.SS` and `$IIII.$SS` are object references;
// `:Name` at the start of a line is a label.
//
// Pure. Tokens view the line's text (the caller keeps it alive). Errors are values.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::basic {

enum class Kw : std::uint8_t {
  none,
  if_,
  then,
  elseif,
  else_,
  endif,  // ENDIF and END_IF
  goto_,
  gosub,
  return_,
  for_,
  to,
  step,
  next,
  setobj,
  getobj,
  and_,
  or_,
  not_,
  en_evt,
  di_evt,
  def_evt_var,
  ret_evt,
  def_tim_var,
  start_tim,
  def_cyc_var,
  start_cyc,
  stop_cyc,
  save,
  load,
};

enum class Tok : std::uint8_t {
  end,     // end of the line (or the start of a comment)
  number,  // value
  objref,  // index, sub
  word,    // name or keyword (kw)
  label,   // `:Name` (text = Name)
  lparen,
  rparen,
  comma,
  plus,
  minus,
  star,
  slash,
  percent,
  amp,
  pipe,
  tilde,
  eq,
  ne,
  lt,
  gt,
  le,
  ge,
};

struct Token {
  Tok kind = Tok::end;
  Kw kw = Kw::none;
  std::uint32_t value = 0;  // number (two's-complement pattern)
  std::uint16_t index = 0;  // objref
  std::uint8_t sub = 0;     // objref
  std::string_view text;    // the characters of the token
};

struct LexedLine {
  std::vector<Token> tokens;  // without the final Tok::end
  std::string error;          // non-empty: the line is not lexically valid
};

// The lines of a program text: CR, LF and CR LF each end a line; a final line without an end counts.
std::vector<std::string_view> split_lines(std::string_view text);

LexedLine lex_line(std::string_view line);

// The keyword a word stands for (case-insensitive), Kw::none if it is none.
Kw keyword(std::string_view word);
// A token for messages: "'THEN'", "end of line", "'$607A.00'".
std::string describe(const Token& t);

}  // namespace mcemu::basic
