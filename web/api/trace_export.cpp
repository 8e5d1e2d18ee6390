#include "web/api/trace_export.hpp"

#include <array>
#include <cstdio>

#include "protocols/slcan/codec.hpp"

namespace mcemu::web::api {

using nlohmann::json;

json event_json(const trace::Event& e) {
  json j{{"seq", e.seq},
         {"timeMs", e.time_ms},
         {"wall", e.wall},
         {"channel", trace::to_string(e.channel)},
         {"dir", trace::to_string(e.dir)},
         {"conn", e.conn != 0 ? json(e.conn) : json(nullptr)},
         {"peer", e.peer.empty() ? json(nullptr) : json(e.peer)},
         {"text", e.text}};
  if (e.flags.overlong) j["overlong"] = true;
  if (e.flags.to_script) j["toScript"] = true;
  if (e.flags.discarded) j["discarded"] = true;
  if (e.flags.ignored) j["ignored"] = true;
  return j;
}

json trace_json(const trace::Ring::Result& r) {
  json events = json::array();
  for (const auto& e : r.events) events.push_back(event_json(e));
  return json{{"events", std::move(events)}, {"nextSeq", r.next_seq}, {"dropped", r.dropped}};
}

std::optional<can::Frame> frame_of_slcan_line(std::string_view line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
  if (line.empty() || (line[0] != 't' && line[0] != 'T' && line[0] != 'r' && line[0] != 'R')) return std::nullopt;
  auto parsed = slcan::parse_line(line);
  if (!std::holds_alternative<slcan::Command>(parsed) && line.size() > 4) {
    parsed = slcan::parse_line(line.substr(0, line.size() - 4));  // a frame with a timestamp (Z1)
  }
  const auto* cmd = std::get_if<slcan::Command>(&parsed);
  if (!cmd || cmd->kind != slcan::CommandKind::frame) return std::nullopt;
  return cmd->frame;
}

std::string candump_frame(const can::Frame& f) {
  std::array<char, 16> id{};
  std::snprintf(id.data(), id.size(), f.extended ? "%08X" : "%03X", f.id);
  std::string out = id.data();
  out += '#';
  if (f.rtr) {
    out += 'R';
    if (f.dlc > 0) out += static_cast<char>('0' + std::min<int>(f.dlc, 8));
    return out;
  }
  static constexpr char k_digits[] = "0123456789ABCDEF";
  for (int i = 0; i < std::min<int>(f.dlc, 8); ++i) {
    out += k_digits[f.data[static_cast<std::size_t>(i)] >> 4];
    out += k_digits[f.data[static_cast<std::size_t>(i)] & 0x0F];
  }
  return out;
}

namespace {

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

std::optional<unsigned> digits(std::string_view s, std::size_t pos, std::size_t n) {
  if (pos + n > s.size()) return std::nullopt;
  unsigned v = 0;
  for (std::size_t i = pos; i < pos + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return std::nullopt;
    v = v * 10 + static_cast<unsigned>(s[i] - '0');
  }
  return v;
}

}  // namespace

std::optional<EpochTime> parse_utc(std::string_view s) {
  // YYYY-MM-DDTHH:MM:SS[.fff…]Z
  const auto y = digits(s, 0, 4), mo = digits(s, 5, 2), d = digits(s, 8, 2);
  const auto h = digits(s, 11, 2), mi = digits(s, 14, 2), se = digits(s, 17, 2);
  if (!y || !mo || !d || !h || !mi || !se || s[4] != '-' || s[7] != '-' || s[10] != 'T' || s[13] != ':' ||
      s[16] != ':' || *mo < 1 || *mo > 12 || *d < 1 || *d > 31 || *h > 23 || *mi > 59 || *se > 60) {
    return std::nullopt;
  }
  std::size_t pos = 19;
  std::int64_t micros = 0;
  if (pos < s.size() && s[pos] == '.') {
    ++pos;
    std::int64_t scale = 100000;
    const std::size_t start = pos;
    while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') {
      micros += scale * (s[pos] - '0');
      scale /= 10;
      ++pos;
    }
    if (pos == start) return std::nullopt;
  }
  if (pos + 1 != s.size() || s[pos] != 'Z') return std::nullopt;
  EpochTime t;
  t.seconds = days_from_civil(*y, *mo, *d) * 86400 + *h * 3600 + *mi * 60 + *se;
  t.micros = micros;
  return t;
}

std::string candump_log(std::span<const trace::Event> events, std::string_view interface_name) {
  std::string out;
  for (const auto& e : events) {
    if (e.channel != trace::Channel::slcan || e.dir == trace::Dir::event || e.flags.overlong) continue;
    const auto frame = frame_of_slcan_line(e.text);
    if (!frame) continue;
    EpochTime t;
    if (const auto wall = parse_utc(e.wall)) {
      t = *wall;
    } else {
      t.seconds = static_cast<std::int64_t>(e.time_ms / 1000);
      t.micros = static_cast<std::int64_t>(e.time_ms % 1000) * 1000;
    }
    std::array<char, 48> stamp{};
    std::snprintf(stamp.data(), stamp.size(), "(%lld.%06lld) ", static_cast<long long>(t.seconds),
                  static_cast<long long>(t.micros));
    out += stamp.data();
    out += interface_name;
    out += ' ';
    out += candump_frame(*frame);
    out += '\n';
  }
  return out;
}

std::string render_control(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\r') {
      out += "<CR>";
    } else if (c == '\n') {
      out += "<LF>";
    } else if (c == '\t') {
      out += "<TAB>";
    } else if (c < 0x20 || c == 0x7F) {
      std::array<char, 8> buf{};
      std::snprintf(buf.data(), buf.size(), "<%02X>", c);
      out += buf.data();
    } else {
      out += ch;
    }
  }
  return out;
}

std::string text_log(std::span<const trace::Event> events) {
  std::string out;
  for (const auto& e : events) {
    out += e.wall.empty() ? "-" : e.wall;
    out += ' ';
    out += std::to_string(e.time_ms);
    out += ' ';
    out += trace::to_string(e.channel);
    out += ' ';
    out += trace::to_string(e.dir);
    out += ' ';
    if (e.conn != 0) {
      out += '#';
      out += std::to_string(e.conn);
    } else {
      out += '-';
    }
    out += ' ';
    out += render_control(e.text);
    if (e.flags.overlong) out += " [overlong]";
    if (e.flags.to_script) out += " [toScript]";
    if (e.flags.discarded) out += " [discarded]";
    if (e.flags.ignored) out += " [ignored]";
    out += '\n';
  }
  return out;
}

}  // namespace mcemu::web::api
