#include "trace/trace.hpp"

#include <algorithm>
#include <array>

namespace mcemu::trace {

namespace {
constexpr std::array<std::string_view, k_channel_count> k_channel_names{"refgo",  "slcan", "udp", "http",
                                                                        "script", "drive", "api"};
}

std::string_view to_string(Channel c) { return k_channel_names[static_cast<std::size_t>(c)]; }

std::string_view to_string(Dir d) {
  switch (d) {
    case Dir::rx: return "rx";
    case Dir::tx: return "tx";
    case Dir::event: break;
  }
  return "event";
}

std::optional<Channel> channel_from_string(std::string_view name) {
  for (std::size_t i = 0; i < k_channel_names.size(); ++i) {
    if (k_channel_names[i] == name) return static_cast<Channel>(i);
  }
  return std::nullopt;
}

std::optional<ChannelSet> parse_channels(std::string_view text) {
  if (text.empty()) return ChannelSet{};
  ChannelSet set = ChannelSet::none();
  while (true) {
    const auto comma = text.find(',');
    const auto name = text.substr(0, comma);
    const auto c = channel_from_string(name);
    if (!c) return std::nullopt;
    set.add(*c);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return set;
}

Ring::Ring(Clocks clocks, std::size_t capacity)
    : clocks_(std::move(clocks)), capacity_(std::max<std::size_t>(capacity, 1)) {}

std::uint64_t Ring::record(Channel channel, Dir dir, std::string text, std::uint64_t conn, std::string peer,
                           Flags flags) {
  Event e;
  e.seq = next_seq_++;
  e.time_ms = clocks_.drive_ms ? clocks_.drive_ms() : 0;
  e.wall = clocks_.wall ? clocks_.wall() : std::string();
  e.channel = channel;
  e.dir = dir;
  e.conn = conn;
  e.peer = std::move(peer);
  e.text = std::move(text);
  e.flags = flags;
  if (events_.size() == capacity_) events_.pop_front();
  events_.push_back(std::move(e));
  if (listener_) listener_(events_.back());
  return events_.back().seq;
}

Ring::Result Ring::query(const Query& q) const {
  Result r;
  const std::uint64_t since = std::max<std::uint64_t>(q.since, 1);
  r.next_seq = std::max(since, next_seq_);
  if (events_.empty()) {
    r.dropped = since < next_seq_ ? next_seq_ - since : 0;
    return r;
  }
  const std::uint64_t oldest = events_.front().seq;
  if (since < oldest) r.dropped = oldest - since;
  // seq is contiguous inside the ring, so the first wanted event is found by arithmetic.
  std::size_t i = since > oldest ? static_cast<std::size_t>(since - oldest) : 0;
  for (; i < events_.size(); ++i) {
    const Event& e = events_[i];
    if (!q.channels.contains(e.channel)) continue;
    if (r.events.size() == q.limit) {
      r.next_seq = e.seq;  // the first event not returned
      return r;
    }
    r.events.push_back(e);
  }
  r.next_seq = std::max(since, next_seq_);
  return r;
}

std::string hex_bytes(std::string_view bytes) {
  static constexpr char k_digits[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (const char ch : bytes) {
    const auto b = static_cast<unsigned char>(ch);
    out += k_digits[b >> 4];
    out += k_digits[b & 0x0F];
  }
  return out;
}

bool is_text(std::string_view bytes) {
  for (const char ch : bytes) {
    const auto b = static_cast<unsigned char>(ch);
    if (b < 0x20 && b != '\r' && b != '\n' && b != '\t') return false;
    if (b == 0x7F) return false;
  }
  return true;
}

std::string text_or_hex(std::string_view bytes) { return is_text(bytes) ? std::string(bytes) : hex_bytes(bytes); }

}  // namespace mcemu::trace
