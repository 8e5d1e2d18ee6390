#include "protocols/refgo/codec.hpp"

#include <limits>
#include <vector>

#include "drive/od/hex.hpp"

namespace mcemu::refgo {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_upper(char c) { return c >= 'A' && c <= 'Z'; }

// A comma-separated field of the OR/OW arguments, without its surrounding spaces.
struct Field {
  std::size_t begin;
  std::size_t end;
};

std::vector<Field> split_fields(std::string_view args) {
  std::vector<Field> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = args.find(',', start);
    const std::size_t stop = comma == std::string_view::npos ? args.size() : comma;
    std::size_t b = start;
    std::size_t e = stop;
    while (b < e && args[b] == ' ') ++b;
    while (e > b && args[e - 1] == ' ') --e;
    out.push_back({b, e});
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

// 1–8 hex digits, optionally followed by H (refgo.md §9.1).
std::optional<std::uint32_t> parse_hex_token(std::string_view t) {
  if (!t.empty() && t.back() == 'H') t.remove_suffix(1);
  if (t.size() > 8) return std::nullopt;
  const auto v = od::parse_hex(t, 0xFFFFFFFF);
  if (!v) return std::nullopt;
  return static_cast<std::uint32_t>(*v);
}

std::optional<std::int64_t> parse_hex_digits(std::string_view t) {
  const auto v = od::parse_hex(t, static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()));
  if (!v) return std::nullopt;
  return static_cast<std::int64_t>(*v);
}

std::optional<std::int64_t> parse_decimal(std::string_view t) {
  bool negative = false;
  if (!t.empty() && (t.front() == '+' || t.front() == '-')) {
    negative = t.front() == '-';
    t.remove_prefix(1);
  }
  if (t.empty()) return std::nullopt;
  // Accumulate the magnitude as unsigned so that INT64_MIN is representable.
  const std::uint64_t limit = negative ? static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) + 1
                                       : static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
  std::uint64_t v = 0;
  for (char c : t) {
    if (!is_digit(c)) return std::nullopt;
    const auto d = static_cast<std::uint64_t>(c - '0');
    if (v > (limit - d) / 10) return std::nullopt;
    v = v * 10 + d;
  }
  if (negative) return v == limit ? std::numeric_limits<std::int64_t>::min() : -static_cast<std::int64_t>(v);
  return static_cast<std::int64_t>(v);
}

}  // namespace

int filter_byte(unsigned char c) {
  if (c == '\t') return ' ';
  if (c < 0x20 || c == 0x7F) return -1;
  return c;
}

Lexed lex(std::string_view line) {
  Lexed l;
  l.echo.assign(line);
  for (char& c : l.echo) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  }
  const std::string_view e(l.echo);
  std::size_t p = 0;
  while (p < e.size() && e[p] == ' ') ++p;
  l.word_pos = p;
  while (p < e.size() && is_upper(e[p])) ++p;
  l.word_len = p - l.word_pos;
  std::size_t end = e.size();
  while (end > l.word_pos && e[end - 1] == ' ') --end;
  l.trim_end = end;
  return l;
}

bool no_argument(std::string_view args) { return args.find_first_not_of(' ') == std::string_view::npos; }

IntArg parse_int_arg(std::string_view args) {
  std::size_t p = 0;
  while (p < args.size() && args[p] == ' ') ++p;
  if (p == args.size()) return {};
  bool negative = false;
  if (args[p] == '+' || args[p] == '-') {
    negative = args[p] == '-';
    ++p;
  }
  const std::size_t digits_begin = p;
  std::int64_t v = 0;
  while (p < args.size() && is_digit(args[p])) {
    v = v * 10 + (args[p] - '0');
    ++p;
    if (p - digits_begin > 10) return {ArgStatus::malformed, 0};
  }
  if (p == digits_begin) return {ArgStatus::malformed, 0};
  while (p < args.size() && args[p] == ' ') ++p;
  if (p != args.size()) return {ArgStatus::malformed, 0};
  return {ArgStatus::ok, negative ? -v : v};
}

std::optional<std::int64_t> parse_value(std::string_view t) {
  if (t.size() > 2 && t[0] == '0' && t[1] == 'X') return parse_hex_digits(t.substr(2));
  if (!t.empty() && t.back() == 'H') return parse_hex_digits(t.substr(0, t.size() - 1));
  return parse_decimal(t);
}

std::optional<ReadArgs> parse_read_args(std::string_view args) {
  const auto f = split_fields(args);
  if (f.size() < 2 || f.size() > 3) return std::nullopt;
  const auto token = [&](const Field& x) { return args.substr(x.begin, x.end - x.begin); };
  const auto index = parse_hex_token(token(f[0]));
  const auto sub = parse_hex_token(token(f[1]));
  if (!index || !sub) return std::nullopt;
  ReadArgs r{*index, *sub, false, f[1].end};
  if (f.size() == 3) {
    if (token(f[2]) != "H") return std::nullopt;
    r.hex = true;
  }
  return r;
}

std::optional<WriteArgs> parse_write_args(std::string_view args) {
  const auto f = split_fields(args);
  if (f.size() != 3) return std::nullopt;
  const auto token = [&](const Field& x) { return args.substr(x.begin, x.end - x.begin); };
  const auto index = parse_hex_token(token(f[0]));
  const auto sub = parse_hex_token(token(f[1]));
  const auto value = parse_value(token(f[2]));
  if (!index || !sub || !value) return std::nullopt;
  return WriteArgs{*index, *sub, *value, f[2].end};
}

}  // namespace mcemu::refgo
