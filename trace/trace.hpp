// The trace ring of web.md §8.6: the newest events of every channel (RefGo lines, SLCAN frames, UDP
// datagrams, HTTP requests, script calls, drive events, API writes, master-lint findings), each with a
// sequence number, drive time and wall time. PURE: the two clocks are injected (the server passes
// drive time and a UTC formatter; tests pass fakes). Producers hold a Ring& (or a Ring*, null =
// tracing off) and call record(); readers query by sequence number and channel set.
//
// Contract: single-threaded (the event loop). Sequence numbers start at 1 and never repeat;
// an event that left the ring is counted in Result::dropped of a query that asks for it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::trace {

// faulhaber: frames of the FAULHABER binary protocol; basic: MC BASIC programs; lint: findings of the
// master lint (docs/lint.md), one event each.
enum class Channel : std::uint8_t { refgo, slcan, udp, http, script, drive, api, faulhaber, basic, lint };
inline constexpr std::size_t k_channel_count = 10;
enum class Dir : std::uint8_t { rx, tx, event };

std::string_view to_string(Channel c);
std::string_view to_string(Dir d);
std::optional<Channel> channel_from_string(std::string_view name);

// A set of channels as a bit mask (bit = 1 << Channel).
struct ChannelSet {
  std::uint32_t bits = (1U << k_channel_count) - 1;  // default: all
  static ChannelSet none() { return ChannelSet{0}; }
  bool contains(Channel c) const { return (bits >> static_cast<unsigned>(c)) & 1U; }
  void add(Channel c) { bits |= 1U << static_cast<unsigned>(c); }
  bool operator==(const ChannelSet&) const = default;
};
// "refgo,udp" → that set; an empty string → all; an unknown name → nullopt.
std::optional<ChannelSet> parse_channels(std::string_view comma_separated);

// Marks of web.md §8.6 and the topic files (refgo.md §2.4, §5.4; slcan-canopen.md §11.2;
// udp-debug.md §2.2).
struct Flags {
  bool overlong = false;
  bool to_script = false;
  bool discarded = false;
  bool ignored = false;
  bool polling = false;  // an HTTP request the pages repeat on a timer (header X-Mcemu-Poll, web.md §8.6)
};

struct Event {
  std::uint64_t seq = 0;
  std::uint64_t time_ms = 0;  // drive time
  std::int64_t wall_ms = -1;  // UTC, ms since 1970; -1 = unknown. format_utc_ms() gives the text
  Channel channel = Channel::drive;
  Dir dir = Dir::event;
  std::uint64_t conn = 0;  // 0 = no connection
  std::string peer;        // "127.0.0.1:53422", empty without a peer
  std::string text;        // raw characters; binary payloads as hex; for Dir::event the event name
  Flags flags;
};

// The bytes of the ring's events (peer, then text), oldest first: a circular buffer whose size
// follows what the ring holds (issue 26: a moving drive records 5–20 events a second, and 10 000 of
// them with a string pair each took ~1.6 MB per drive). Positions are logical (they only grow). The
// buffer grows by half until it holds its bytes and, once only a quarter of it is in use, shrinks
// to twice what it holds: a burst of long texts does not keep its memory once it has left the ring.
class ByteFifo {
 public:
  static constexpr std::size_t k_min_capacity = 256;

  // Appends a then b; returns the position of a's first byte.
  std::uint64_t push(std::string_view a, std::string_view b);
  // Drops the n oldest bytes (n ≤ size()).
  void pop(std::size_t n);
  // The n bytes from position at (still held) into out (its capacity reused).
  void copy(std::uint64_t at, std::size_t n, std::string& out) const;

  std::size_t size() const { return static_cast<std::size_t>(tail_ - head_); }
  std::size_t capacity() const { return buf_.size(); }

 private:
  void write(std::uint64_t at, std::string_view bytes);
  void reallocate(std::size_t capacity);

  std::vector<char> buf_;   // logical position p is buf_[p % size]; empty until the first byte
  std::uint64_t head_ = 0;  // the oldest byte held
  std::uint64_t tail_ = 0;  // one past the newest
};

class Ring {
 public:
  static constexpr std::size_t k_default_capacity = 10000;

  struct Clocks {
    std::function<std::uint64_t()> drive_ms;
    std::function<std::int64_t()> wall_ms;  // UTC, ms since 1970
  };

  explicit Ring(Clocks clocks, std::size_t capacity = k_default_capacity);

  // Appends one event (seq, time and wall filled in here) and returns its seq. Once the ring is
  // full the oldest slot is reused in place and its bytes leave the byte buffer first, so a steady
  // stream of events allocates nothing. A peer longer than 65 535 bytes is cut there (peers are
  // "address:port").
  std::uint64_t record(Channel channel, Dir dir, std::string_view text, std::uint64_t conn = 0,
                       std::string_view peer = {}, Flags flags = {});

  struct Query {
    std::uint64_t since = 0;  // first seq wanted
    ChannelSet channels;
    std::size_t limit = 500;
    bool exclude_polling = false;  // leave out the events marked `polling`
  };
  struct Result {
    std::vector<Event> events;
    std::uint64_t next_seq = 1;  // the `since` of the next query
    std::uint64_t dropped = 0;   // events with seq >= since that had already left the ring
  };
  Result query(const Query& q) const;

  // Called for every recorded event, after it is in the ring (the WebSocket trace channel).
  void set_listener(std::function<void(const Event&)> listener) { listener_ = std::move(listener); }

  std::uint64_t next_seq() const { return next_seq_; }
  std::size_t size() const { return slots_.size(); }
  std::size_t capacity() const { return capacity_; }
  // Bytes the ring holds for its events' peers and texts, and the buffer that holds them (tests,
  // benchmarks).
  std::size_t text_bytes() const { return bytes_.size(); }
  std::size_t text_capacity() const { return bytes_.capacity(); }

 private:
  // One event without its seq (the oldest slot's is next_seq_ - size(), the rest follow) and with
  // its peer and text in bytes_: 40 bytes.
  struct Slot {
    std::uint64_t time_ms = 0;
    std::int64_t wall_ms = -1;
    std::uint64_t conn = 0;
    std::uint64_t at = 0;  // position of the peer's first byte in bytes_, the text after it
    std::uint32_t text_size = 0;
    std::uint16_t peer_size = 0;
    Channel channel = Channel::drive;
    Dir dir = Dir::event;
    std::uint8_t flags = 0;  // Flags, one bit each
  };
  const Slot& at(std::size_t i) const { return slots_[(head_ + i) % slots_.size()]; }
  void fill(Event& e, const Slot& s, std::uint64_t seq) const;

  Clocks clocks_;
  std::size_t capacity_;
  // Grows to capacity_, then circular: slots_[head_] is the oldest event.
  std::vector<Slot> slots_;
  std::size_t head_ = 0;
  std::uint64_t next_seq_ = 1;
  ByteFifo bytes_;
  Event scratch_;             // what the listener is shown (its strings' capacity reused)
  bool in_listener_ = false;  // a listener that records gets a fresh Event for the inner one
  std::function<void(const Event&)> listener_;
};

// "2026-01-15T10:15:02.123Z" (ISO 8601, UTC, milliseconds) of a Unix time in ms; "" when negative.
// Arithmetic only (no gmtime/strftime): events keep the number, readers format it.
std::string format_utc_ms(std::int64_t unix_ms);

// Hex of a binary payload ("0A1B…", upper case), as web.md §8.6 asks for binary data.
std::string hex_bytes(std::string_view bytes);
// True when the payload is text: no control bytes other than CR, LF and TAB (bytes ≥ 0x80 count as
// text, UTF-8). text_or_hex() gives text as it is and anything else as hex_bytes().
bool is_text(std::string_view bytes);
std::string text_or_hex(std::string_view bytes);

}  // namespace mcemu::trace
