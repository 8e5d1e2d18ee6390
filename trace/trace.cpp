#include "trace/trace.hpp"

#include <algorithm>
#include <array>
#include <limits>

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

// ---- ByteFifo

void ByteFifo::write(std::uint64_t at, std::string_view bytes) {
  if (bytes.empty()) return;  // also: nothing held yet, the buffer may be empty
  const auto start = static_cast<std::size_t>(at % buf_.size());
  const std::size_t first = std::min(bytes.size(), buf_.size() - start);
  std::copy_n(bytes.data(), first, buf_.data() + start);
  std::copy_n(bytes.data() + first, bytes.size() - first, buf_.data());
}

void ByteFifo::copy(std::uint64_t at, std::size_t n, std::string& out) const {
  out.clear();
  if (n == 0) return;
  const auto start = static_cast<std::size_t>(at % buf_.size());
  const std::size_t first = std::min(n, buf_.size() - start);
  out.append(buf_.data() + start, first);
  out.append(buf_.data(), n - first);
}

void ByteFifo::reallocate(std::size_t capacity) {
  std::string live;
  copy(head_, size(), live);
  buf_ = std::vector<char>(capacity);  // a new vector: a smaller one gives the old memory back
  write(head_, live);
}

std::uint64_t ByteFifo::push(std::string_view a, std::string_view b) {
  const std::size_t need = size() + a.size() + b.size();
  if (need > buf_.size()) {
    std::size_t capacity = std::max(k_min_capacity, buf_.size());
    while (capacity < need) capacity += capacity / 2;
    reallocate(capacity);
  }
  const std::uint64_t at = tail_;
  write(tail_, a);
  tail_ += a.size();
  write(tail_, b);
  tail_ += b.size();
  return at;
}

void ByteFifo::pop(std::size_t n) {
  head_ += std::min<std::uint64_t>(n, tail_ - head_);
  // a quarter in use: down to twice what is held
  if (buf_.size() > k_min_capacity && size() <= buf_.size() / 4) reallocate(std::max(k_min_capacity, 2 * size()));
}

// ---- Ring

Ring::Ring(Clocks clocks, std::size_t capacity)
    : clocks_(std::move(clocks)), capacity_(std::max<std::size_t>(capacity, 1)) {}

namespace {

constexpr std::uint8_t k_polling_bit = 16;

std::uint8_t pack(const Flags& f) {
  return static_cast<std::uint8_t>((f.overlong ? 1U : 0U) | (f.to_script ? 2U : 0U) | (f.discarded ? 4U : 0U) |
                                   (f.ignored ? 8U : 0U) | (f.polling ? k_polling_bit : 0U));
}

Flags unpack(std::uint8_t bits) {
  return Flags{(bits & 1U) != 0, (bits & 2U) != 0, (bits & 4U) != 0, (bits & 8U) != 0, (bits & 16U) != 0};
}

}  // namespace

void Ring::fill(Event& e, const Slot& s, std::uint64_t seq) const {
  e.seq = seq;
  e.time_ms = s.time_ms;
  e.wall_ms = s.wall_ms;
  e.channel = s.channel;
  e.dir = s.dir;
  e.conn = s.conn;
  bytes_.copy(s.at, s.peer_size, e.peer);
  bytes_.copy(s.at + s.peer_size, s.text_size, e.text);
  e.flags = unpack(s.flags);
}

std::uint64_t Ring::record(Channel channel, Dir dir, std::string_view text, std::uint64_t conn, std::string_view peer,
                           Flags flags) {
  Slot* s = nullptr;
  if (slots_.size() < capacity_) {
    // grow by doubling, but never past capacity_ (the vector's own doubling would overshoot it)
    if (slots_.size() == slots_.capacity())
      slots_.reserve(std::min(capacity_, std::max<std::size_t>(16, 2 * slots_.size())));
    s = &slots_.emplace_back();
  } else {
    s = &slots_[head_];
    head_ = (head_ + 1) % slots_.size();
    bytes_.pop(std::size_t{s->peer_size} + s->text_size);  // the oldest event's bytes are the oldest bytes
  }
  peer = peer.substr(0, std::numeric_limits<std::uint16_t>::max());
  s->time_ms = clocks_.drive_ms ? clocks_.drive_ms() : 0;
  s->wall_ms = clocks_.wall_ms ? clocks_.wall_ms() : -1;
  s->conn = conn;
  s->at = bytes_.push(peer, text);
  s->text_size = static_cast<std::uint32_t>(text.size());
  s->peer_size = static_cast<std::uint16_t>(peer.size());
  s->channel = channel;
  s->dir = dir;
  s->flags = pack(flags);
  const std::uint64_t seq = next_seq_++;
  if (listener_ && !in_listener_) {
    fill(scratch_, *s, seq);
    in_listener_ = true;
    listener_(scratch_);
    in_listener_ = false;
  } else if (listener_) {  // recorded by the listener itself: scratch_ is still being shown
    Event e;
    fill(e, *s, seq);
    listener_(e);
  }
  return seq;
}

Ring::Result Ring::query(const Query& q) const {
  Result r;
  const std::uint64_t since = std::max<std::uint64_t>(q.since, 1);
  r.next_seq = std::max(since, next_seq_);
  if (slots_.empty()) {
    r.dropped = since < next_seq_ ? next_seq_ - since : 0;
    return r;
  }
  const std::uint64_t oldest = next_seq_ - slots_.size();
  if (since < oldest) r.dropped = oldest - since;
  // seq is contiguous inside the ring, so the first wanted event is found by arithmetic.
  std::size_t i = since > oldest ? static_cast<std::size_t>(since - oldest) : 0;
  for (; i < slots_.size(); ++i) {
    const Slot& s = at(i);
    if (!q.channels.contains(s.channel) || (q.exclude_polling && (s.flags & k_polling_bit) != 0)) continue;
    if (r.events.size() == q.limit) {
      r.next_seq = oldest + i;  // the first event not returned
      return r;
    }
    fill(r.events.emplace_back(), s, oldest + i);
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
