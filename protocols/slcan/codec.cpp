#include "protocols/slcan/codec.hpp"

namespace mcemu::slcan {
namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Exactly `text` as hex; nullopt if any digit is not hex.
std::optional<std::uint32_t> parse_hex(std::string_view text) {
  std::uint32_t v = 0;
  for (char c : text) {
    const int d = hex_value(c);
    if (d < 0) return std::nullopt;
    v = (v << 4) | static_cast<std::uint32_t>(d);
  }
  return v;
}

ParseResult simple(CommandKind kind, char letter, std::string_view rest) {
  if (!rest.empty()) return ParseError::unknown_command;
  return Command{kind, letter, 0, {}};
}

// A command letter followed by exactly one decimal digit in [0, max].
ParseResult digit_arg(CommandKind kind, char letter, std::string_view rest, unsigned max) {
  if (rest.size() != 1 || rest[0] < '0' || rest[0] > '9') return ParseError::bad_argument;
  const auto d = static_cast<unsigned>(rest[0] - '0');
  if (d > max) return ParseError::bad_argument;
  return Command{kind, letter, d, {}};
}

ParseResult hex_arg(CommandKind kind, char letter, std::string_view rest, std::size_t digits) {
  if (rest.size() != digits) return ParseError::bad_argument;
  auto v = parse_hex(rest);
  if (!v) return ParseError::bad_argument;
  return Command{kind, letter, *v, {}};
}

// §3.5: t III L D…, T IIIIIIII L D…, r III L, R IIIIIIII L; checks in the order of the spec.
ParseResult frame_line(char letter, std::string_view line) {
  const bool extended = letter == 'T' || letter == 'R';
  const bool rtr = letter == 'r' || letter == 'R';
  const std::size_t id_digits = extended ? 8 : 3;
  const std::size_t dlc_pos = 1 + id_digits;
  if (line.size() <= dlc_pos) return ParseError::bad_length;
  const char l = line[dlc_pos];
  if (l < '0' || l > '8') return ParseError::bad_dlc;
  const auto dlc = static_cast<std::uint8_t>(l - '0');
  const std::size_t expected = dlc_pos + 1 + (rtr ? 0 : 2u * dlc);
  if (line.size() != expected) return ParseError::bad_length;
  const auto id = parse_hex(line.substr(1, id_digits));
  if (!id) return ParseError::bad_hex;
  Command c{CommandKind::frame, letter, 0, {}};
  for (std::size_t i = 0; i < (rtr ? 0u : dlc); ++i) {
    const auto byte = parse_hex(line.substr(dlc_pos + 1 + 2 * i, 2));
    if (!byte) return ParseError::bad_hex;
    c.frame.data[i] = static_cast<std::uint8_t>(*byte);
  }
  if (*id > (extended ? 0x1FFFFFFFu : 0x7FFu)) return ParseError::id_range;
  c.frame.id = *id;
  c.frame.extended = extended;
  c.frame.rtr = rtr;
  c.frame.dlc = dlc;
  return c;
}

}  // namespace

ParseResult parse_line(std::string_view line) {
  for (char ch : line) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x21 || c > 0x7E) return ParseError::non_printable;
  }
  if (line.empty()) return Command{};
  const char letter = line[0];
  const std::string_view rest = line.substr(1);
  switch (letter) {
    case 'O': return simple(CommandKind::open, letter, rest);
    case 'L': return simple(CommandKind::listen, letter, rest);
    case 'C': return simple(CommandKind::close, letter, rest);
    case 'V': return simple(CommandKind::version, letter, rest);
    case 'v': return simple(CommandKind::version_lower, letter, rest);
    case 'N': return simple(CommandKind::serial, letter, rest);
    case 'F': return simple(CommandKind::flags, letter, rest);
    case 'S': return digit_arg(CommandKind::bitrate, letter, rest, 9);
    case 'Z': return digit_arg(CommandKind::timestamps, letter, rest, 1);
    case 'W': return digit_arg(CommandKind::setting, letter, rest, 2);
    case 'X': return digit_arg(CommandKind::setting, letter, rest, 1);
    case 'Q': return digit_arg(CommandKind::setting, letter, rest, 2);
    case 'U': return digit_arg(CommandKind::setting, letter, rest, 6);
    case 's': return hex_arg(CommandKind::btr, letter, rest, 4);
    case 'M': return hex_arg(CommandKind::acceptance_code, letter, rest, 8);
    case 'm': return hex_arg(CommandKind::acceptance_mask, letter, rest, 8);
    case 't':
    case 'T':
    case 'r':
    case 'R': return frame_line(letter, line);
    default: return ParseError::unknown_command;
  }
}

std::string_view to_string(ParseError e) {
  switch (e) {
    case ParseError::overlong: return "line longer than 64 bytes";
    case ParseError::non_printable: return "byte outside 0x21..0x7E";
    case ParseError::unknown_command: return "unknown command";
    case ParseError::bad_argument: return "bad parameter";
    case ParseError::bad_dlc: return "DLC not 0..8";
    case ParseError::bad_length: return "line length does not match the DLC";
    case ParseError::bad_hex: return "not a hex digit";
    case ParseError::id_range: return "identifier out of range";
  }
  return "error";
}

std::string encode_frame(const can::Frame& frame, std::optional<std::chrono::milliseconds> timestamp) {
  static constexpr char k_hex[] = "0123456789ABCDEF";
  const auto put_hex = [](std::string& out, std::uint32_t v, int digits) {
    for (int i = digits - 1; i >= 0; --i) out.push_back(k_hex[(v >> (4 * i)) & 0xF]);
  };
  const std::uint8_t dlc = frame.dlc > 8 ? 8 : frame.dlc;
  std::string out;
  out.reserve(32);
  if (frame.extended) {
    out.push_back(frame.rtr ? 'R' : 'T');
    put_hex(out, frame.id & 0x1FFFFFFFu, 8);
  } else {
    out.push_back(frame.rtr ? 'r' : 't');
    put_hex(out, frame.id & 0x7FFu, 3);
  }
  out.push_back(static_cast<char>('0' + dlc));
  if (!frame.rtr) {
    for (std::uint8_t i = 0; i < dlc; ++i) put_hex(out, frame.data[i], 2);
  }
  if (timestamp) {
    const auto ms = timestamp->count() % 60000;
    put_hex(out, static_cast<std::uint32_t>(ms < 0 ? ms + 60000 : ms), 4);
  }
  out.push_back('\r');
  return out;
}

}  // namespace mcemu::slcan
