#include "scripting/basic/lexer.hpp"

#include <array>
#include <utility>

namespace mcemu::basic {
namespace {

bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_alnum(char c) { return is_alpha(c) || is_digit(c); }
int hex_value(char c) {
  if (is_digit(c)) return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

constexpr std::array<std::pair<std::string_view, Kw>, 29> k_keywords{{
    {"IF", Kw::if_},
    {"THEN", Kw::then},
    {"ELSEIF", Kw::elseif},
    {"ELSE", Kw::else_},
    {"ENDIF", Kw::endif},
    {"END_IF", Kw::endif},
    {"GOTO", Kw::goto_},
    {"GOSUB", Kw::gosub},
    {"RETURN", Kw::return_},
    {"FOR", Kw::for_},
    {"TO", Kw::to},
    {"STEP", Kw::step},
    {"NEXT", Kw::next},
    {"SETOBJ", Kw::setobj},
    {"GETOBJ", Kw::getobj},
    {"AND", Kw::and_},
    {"OR", Kw::or_},
    {"NOT", Kw::not_},
    {"EN_EVT", Kw::en_evt},
    {"DI_EVT", Kw::di_evt},
    {"DEF_EVT_VAR", Kw::def_evt_var},
    {"RET_EVT", Kw::ret_evt},
    {"DEF_TIM_VAR", Kw::def_tim_var},
    {"START_TIM", Kw::start_tim},
    {"DEF_CYC_VAR", Kw::def_cyc_var},
    {"START_CYC", Kw::start_cyc},
    {"STOP_CYC", Kw::stop_cyc},
    {"SAVE", Kw::save},
    {"LOAD", Kw::load},
}};

// Hex digits at line[i…]: the value (≤ 32 bits) and the position after them; ok false when there
// is no digit or the value does not fit.
struct HexScan {
  bool ok = false;
  std::uint64_t value = 0;
  std::size_t next = 0;
};
HexScan scan_hex(std::string_view line, std::size_t i) {
  HexScan s;
  const std::size_t start = i;
  while (i < line.size() && hex_value(line[i]) >= 0) {
    s.value = s.value * 16 + static_cast<std::uint64_t>(hex_value(line[i]));
    if (s.value > 0xFFFFFFFFULL) return s;
    ++i;
  }
  s.ok = i > start;
  s.next = i;
  return s;
}

}  // namespace

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\r' && text[i] != '\n') continue;
    lines.push_back(text.substr(start, i - start));
    if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    start = i + 1;
  }
  if (start < text.size()) lines.push_back(text.substr(start));
  return lines;
}

Kw keyword(std::string_view word) {
  for (const auto& [name, kw] : k_keywords) {
    if (iequals(word, name)) return kw;
  }
  return Kw::none;
}

std::string describe(const Token& t) {
  if (t.kind == Tok::end) return "end of line";
  std::string s;  // not "'" + … + "'": GCC 12 reports a false -Wrestrict for that
  s.reserve(t.text.size() + 2);
  s += '\'';
  s += t.text;
  s += '\'';
  return s;
}

LexedLine lex_line(std::string_view line) {
  LexedLine out;
  auto fail = [&](std::string message) {
    out.tokens.clear();
    out.error = std::move(message);
    return out;
  };
  std::size_t i = 0;
  while (i < line.size()) {
    const char c = line[i];
    if (c == ' ' || c == '\t') {
      ++i;
      continue;
    }
    if (c == '\'') break;  // comment to the end of the line
    const std::size_t start = i;
    Token t;
    if (c == ':') {
      if (!out.tokens.empty()) return fail("':' may only start a label at the beginning of a line");
      ++i;
      if (i >= line.size() || !is_alpha(line[i])) return fail("a label name (letters, digits, _) must follow ':'");
      while (i < line.size() && is_alnum(line[i])) ++i;
      t.kind = Tok::label;
      t.text = line.substr(start + 1, i - start - 1);
      out.tokens.push_back(t);
      continue;
    }
    if (is_alpha(c)) {
      while (i < line.size() && is_alnum(line[i])) ++i;
      t.kind = Tok::word;
      t.text = line.substr(start, i - start);
      t.kw = keyword(t.text);
      out.tokens.push_back(t);
      continue;
    }
    if (is_digit(c)) {
      std::uint64_t v = 0;
      while (i < line.size() && is_digit(line[i])) {
        v = v * 10 + static_cast<std::uint64_t>(line[i] - '0');
        if (v > 0xFFFFFFFFULL)
          return fail("number '" + std::string(line.substr(start, i + 1 - start)) + "…' is too large");
        ++i;
      }
      if (i < line.size() && (is_alpha(line[i]) || line[i] == '.')) {
        return fail("malformed number '" + std::string(line.substr(start, i + 1 - start)) + "'");
      }
      t.kind = Tok::number;
      t.value = static_cast<std::uint32_t>(v);
      t.text = line.substr(start, i - start);
      out.tokens.push_back(t);
      continue;
    }
    if (c == '$') {
      const HexScan h = scan_hex(line, i + 1);
      if (!h.ok) return fail("malformed hexadecimal number after '$'");
      i = h.next;
      if (i < line.size() && line[i] == '.') {
        // an object reference $IIII.SS or $IIII.$SS
        if (h.value > 0xFFFF)
          return fail("object index '" + std::string(line.substr(start, i - start)) + "' is too large");
        std::size_t j = i + 1;
        if (j < line.size() && line[j] == '$') ++j;
        const HexScan s = scan_hex(line, j);
        if (!s.ok || s.value > 0xFF) return fail("an object reference needs a sub-index $00 … $FF after '.'");
        i = s.next;
        if (i < line.size() && (is_alnum(line[i]) || line[i] == '.' || line[i] == '$')) {
          return fail("malformed object reference '" + std::string(line.substr(start, i + 1 - start)) + "'");
        }
        t.kind = Tok::objref;
        t.index = static_cast<std::uint16_t>(h.value);
        t.sub = static_cast<std::uint8_t>(s.value);
      } else {
        if (i < line.size() && (is_alnum(line[i]) || line[i] == '$')) {
          return fail("malformed hexadecimal number '" + std::string(line.substr(start, i + 1 - start)) + "'");
        }
        t.kind = Tok::number;
        t.value = static_cast<std::uint32_t>(h.value);
      }
      t.text = line.substr(start, i - start);
      out.tokens.push_back(t);
      continue;
    }
    const char n = i + 1 < line.size() ? line[i + 1] : '\0';
    std::size_t len = 1;
    switch (c) {
      case '(': t.kind = Tok::lparen; break;
      case ')': t.kind = Tok::rparen; break;
      case ',': t.kind = Tok::comma; break;
      case '+': t.kind = Tok::plus; break;
      case '-': t.kind = Tok::minus; break;
      case '*': t.kind = Tok::star; break;
      case '/': t.kind = Tok::slash; break;
      case '%': t.kind = Tok::percent; break;
      case '&': t.kind = Tok::amp; break;
      case '|': t.kind = Tok::pipe; break;
      case '~': t.kind = Tok::tilde; break;
      case '=': t.kind = Tok::eq; break;
      case '<':
        t.kind = n == '>' ? Tok::ne : n == '=' ? Tok::le : Tok::lt;
        len = t.kind == Tok::lt ? 1 : 2;
        break;
      case '>':
        t.kind = n == '=' ? Tok::ge : Tok::gt;
        len = t.kind == Tok::gt ? 1 : 2;
        break;
      default: {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x21 && u < 0x7F) return fail(std::string("unexpected character '") + c + "'");
        char hex[8];
        static constexpr char k_digits[] = "0123456789ABCDEF";
        hex[0] = '0';
        hex[1] = 'x';
        hex[2] = k_digits[u >> 4];
        hex[3] = k_digits[u & 0xF];
        return fail("unexpected byte " + std::string(hex, 4) + " (only comments may hold other characters)");
      }
    }
    i += len;
    t.text = line.substr(start, len);
    out.tokens.push_back(t);
  }
  return out;
}

}  // namespace mcemu::basic
