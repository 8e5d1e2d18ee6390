#include "web/api/trace_export.hpp"

#include <array>
#include <cstdio>

#include "protocols/slcan/codec.hpp"

namespace mcemu::web::api {

using nlohmann::json;

json event_json(const trace::Event& e) {
  json j{{"seq", e.seq},
         {"timeMs", e.time_ms},
         {"wall", e.wall_ms >= 0 ? json(trace::format_utc_ms(e.wall_ms)) : json(nullptr)},
         {"channel", trace::to_string(e.channel)},
         {"dir", trace::to_string(e.dir)},
         {"conn", e.conn != 0 ? json(e.conn) : json(nullptr)},
         {"peer", e.peer.empty() ? json(nullptr) : json(e.peer)},
         {"text", e.text}};
  if (e.flags.overlong) j["overlong"] = true;
  if (e.flags.to_script) j["toScript"] = true;
  if (e.flags.discarded) j["discarded"] = true;
  if (e.flags.ignored) j["ignored"] = true;
  if (e.flags.polling) j["polling"] = true;
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

std::string candump_log(std::span<const trace::Event> events, std::string_view interface_name) {
  std::string out;
  for (const auto& e : events) {
    if (e.channel != trace::Channel::slcan || e.dir == trace::Dir::event || e.flags.overlong) continue;
    const auto frame = frame_of_slcan_line(e.text);
    if (!frame) continue;
    // the wall time, or the drive time for an event without one
    const std::int64_t ms = e.wall_ms >= 0 ? e.wall_ms : static_cast<std::int64_t>(e.time_ms);
    std::array<char, 48> stamp{};
    std::snprintf(stamp.data(), stamp.size(), "(%lld.%06lld) ", static_cast<long long>(ms / 1000),
                  static_cast<long long>(ms % 1000 * 1000));
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
    out += e.wall_ms >= 0 ? trace::format_utc_ms(e.wall_ms) : std::string("-");
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
    if (e.flags.polling) out += " [polling]";
    out += '\n';
  }
  return out;
}

}  // namespace mcemu::web::api
