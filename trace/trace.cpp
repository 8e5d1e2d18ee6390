#include "trace/trace.hpp"

#include <algorithm>
#include <array>

namespace mcemu::trace {

namespace {
constexpr std::array<std::string_view, k_channel_count> k_channel_names{
    "refgo", "slcan", "udp", "http", "script", "drive", "api", "faulhaber", "basic", "lint"};
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

std::uint64_t Ring::record(Channel channel, Dir dir, std::string_view text, std::uint64_t conn, std::string_view peer,
                           Flags flags) {
  Event* e = nullptr;
  if (events_.size() < capacity_) {
    // grow by doubling, but never past capacity_ (the vector's own doubling would overshoot it)
    if (events_.size() == events_.capacity())
      events_.reserve(std::min(capacity_, std::max<std::size_t>(16, 2 * events_.size())));
    e = &events_.emplace_back();
  } else {
    e = &events_[head_];
    head_ = (head_ + 1) % events_.size();
  }
  e->seq = next_seq_++;
  e->time_ms = clocks_.drive_ms ? clocks_.drive_ms() : 0;
  e->wall_ms = clocks_.wall_ms ? clocks_.wall_ms() : -1;
  e->channel = channel;
  e->dir = dir;
  e->conn = conn;
  e->peer.assign(peer);
  e->text.assign(text);
  e->flags = flags;
  const std::uint64_t seq = e->seq;
  if (listener_) listener_(*e);
  return seq;
}

Ring::Result Ring::query(const Query& q) const {
  Result r;
  const std::uint64_t since = std::max<std::uint64_t>(q.since, 1);
  r.next_seq = std::max(since, next_seq_);
  if (events_.empty()) {
    r.dropped = since < next_seq_ ? next_seq_ - since : 0;
    return r;
  }
  const std::uint64_t oldest = at(0).seq;
  if (since < oldest) r.dropped = oldest - since;
  // seq is contiguous inside the ring, so the first wanted event is found by arithmetic.
  std::size_t i = since > oldest ? static_cast<std::size_t>(since - oldest) : 0;
  for (; i < events_.size(); ++i) {
    const Event& e = at(i);
    if (!q.channels.contains(e.channel) || (q.exclude_polling && e.flags.polling)) continue;
    if (r.events.size() == q.limit) {
      r.next_seq = e.seq;  // the first event not returned
      return r;
    }
    r.events.push_back(e);
  }
  r.next_seq = std::max(since, next_seq_);
  return r;
}

namespace {
// Year, month, day of a count of days since 1970-01-01 (proleptic Gregorian; H. Hinnant's
// civil_from_days).
struct Civil {
  std::int64_t y;
  unsigned m, d;
};
Civil civil_from_days(std::int64_t z) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  return {static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0), m, d};
}
void put_digits(std::string& out, std::int64_t v, int width) {
  char buf[20];
  for (int i = width - 1; i >= 0; --i) {
    buf[i] = static_cast<char>('0' + v % 10);
    v /= 10;
  }
  out.append(buf, static_cast<std::size_t>(width));
}
}  // namespace

std::string format_utc_ms(std::int64_t unix_ms) {
  if (unix_ms < 0) return {};
  const std::int64_t secs = unix_ms / 1000;
  const std::int64_t day_secs = secs % 86400;
  const Civil c = civil_from_days(secs / 86400);
  std::string out;
  out.reserve(24);
  put_digits(out, c.y % 10000, 4);
  out += '-';
  put_digits(out, c.m, 2);
  out += '-';
  put_digits(out, c.d, 2);
  out += 'T';
  put_digits(out, day_secs / 3600, 2);
  out += ':';
  put_digits(out, day_secs / 60 % 60, 2);
  out += ':';
  put_digits(out, day_secs % 60, 2);
  out += '.';
  put_digits(out, unix_ms % 1000, 3);
  out += 'Z';
  return out;
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
