// The trace ring (web.md §8.6): sequence numbers, capacity, `since`/`limit`/channel queries,
// `dropped` counting, channel parsing.
#include "trace/trace.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace mcemu::trace {
namespace {

Ring::Query since(std::uint64_t seq) {
  Ring::Query q;
  q.since = seq;
  return q;
}

struct Fixture {
  std::uint64_t now = 0;
  Ring ring{Ring::Clocks{[this] { return now; }, [] { return std::int64_t{1768472102123}; }},
            5};  // 2026-01-15T10:15:02.123Z
};

TEST(TraceRing, RecordsWithSequenceAndClocks) {
  Fixture f;
  f.now = 42;
  EXPECT_EQ(f.ring.record(Channel::refgo, Dir::rx, "TP\r", 3, "127.0.0.1:5000"), 1U);
  f.now = 43;
  EXPECT_EQ(f.ring.record(Channel::udp, Dir::tx, "x", 0, {}, Flags{.ignored = true}), 2U);
  const auto r = f.ring.query({});
  ASSERT_EQ(r.events.size(), 2U);
  EXPECT_EQ(r.events[0].time_ms, 42U);
  EXPECT_EQ(r.events[0].conn, 3U);
  EXPECT_EQ(r.events[0].peer, "127.0.0.1:5000");
  EXPECT_EQ(r.events[0].text, "TP\r");
  EXPECT_EQ(r.events[0].wall_ms, 1768472102123);
  EXPECT_TRUE(r.events[1].flags.ignored);
  EXPECT_EQ(r.next_seq, 3U);
  EXPECT_EQ(r.dropped, 0U);
}

TEST(TraceRing, KeepsTheNewestAndCountsDropped) {
  Fixture f;
  for (int i = 0; i < 8; ++i) f.ring.record(Channel::drive, Dir::event, std::to_string(i));
  EXPECT_EQ(f.ring.size(), 5U);
  const auto r = f.ring.query(since(1));
  ASSERT_EQ(r.events.size(), 5U);
  EXPECT_EQ(r.events.front().seq, 4U);
  EXPECT_EQ(r.dropped, 3U);
  EXPECT_EQ(r.next_seq, 9U);
  const auto later = f.ring.query(since(6));
  ASSERT_EQ(later.events.size(), 3U);
  EXPECT_EQ(later.events.front().seq, 6U);
  EXPECT_EQ(later.dropped, 0U);
}

TEST(TraceRing, LimitAndChannelFilter) {
  Fixture f;
  f.ring.record(Channel::refgo, Dir::rx, "a");
  f.ring.record(Channel::slcan, Dir::rx, "b");
  f.ring.record(Channel::refgo, Dir::tx, "c");
  f.ring.record(Channel::refgo, Dir::tx, "d");
  const auto refgo = *parse_channels("refgo");
  const auto r = f.ring.query({.since = 0, .channels = refgo, .limit = 2});
  ASSERT_EQ(r.events.size(), 2U);
  EXPECT_EQ(r.events[0].text, "a");
  EXPECT_EQ(r.events[1].text, "c");
  EXPECT_EQ(r.next_seq, 4U);  // "d" is next
  const auto rest = f.ring.query({.since = r.next_seq, .channels = refgo, .limit = 2});
  ASSERT_EQ(rest.events.size(), 1U);
  EXPECT_EQ(rest.events[0].text, "d");
  EXPECT_EQ(rest.next_seq, 5U);
}

// web.md §8.6: the pages' own polling (events marked `polling`) can be left out; `limit` counts
// only the events returned, and next_seq continues after the last one examined.
TEST(TraceRing, ExcludePollingLeavesTheMarkedEventsOut) {
  Fixture f;
  f.ring.record(Channel::http, Dir::rx, "POST /api/v1/objects/read", 1, {}, Flags{.polling = true});
  f.ring.record(Channel::http, Dir::rx, "PUT /api/v1/objects/6083h/0", 1);
  f.ring.record(Channel::http, Dir::tx, "200", 1, {}, Flags{.polling = true});
  f.ring.record(Channel::http, Dir::tx, "200", 1);
  EXPECT_EQ(f.ring.query({}).events.size(), 4U) << "kept by default";
  auto r = f.ring.query({.since = 0, .channels = ChannelSet{}, .limit = 1, .exclude_polling = true});
  ASSERT_EQ(r.events.size(), 1U);
  EXPECT_EQ(r.events[0].text, "PUT /api/v1/objects/6083h/0");
  r = f.ring.query({.since = r.next_seq, .channels = ChannelSet{}, .limit = 1, .exclude_polling = true});
  ASSERT_EQ(r.events.size(), 1U);
  EXPECT_EQ(r.events[0].seq, 4U);
  EXPECT_FALSE(r.events[0].flags.polling);
  EXPECT_EQ(r.next_seq, 5U);
}

TEST(TraceRing, SinceInTheFutureReturnsNothing) {
  Fixture f;
  f.ring.record(Channel::api, Dir::event, "x");
  const auto r = f.ring.query(since(100));
  EXPECT_TRUE(r.events.empty());
  EXPECT_EQ(r.next_seq, 100U);
  EXPECT_EQ(r.dropped, 0U);
}

TEST(TraceRing, ListenerSeesEveryEvent) {
  Fixture f;
  std::vector<std::uint64_t> seen;
  f.ring.set_listener([&](const Event& e) { seen.push_back(e.seq); });
  f.ring.record(Channel::http, Dir::rx, "GET / HTTP/1.1");
  f.ring.record(Channel::http, Dir::tx, "200");
  EXPECT_EQ(seen, (std::vector<std::uint64_t>{1, 2}));
}

// The ring against a plain model (a deque of whole events) over many records of every size around
// the byte buffer's growth and wrap-around: same events, seqs, fields and dropped counts.
TEST(TraceRing, MatchesAPlainModelThroughWrapAroundsAndGrowth) {
  std::uint64_t now = 0;
  Ring ring{Ring::Clocks{[&] { return now; }, [&] { return static_cast<std::int64_t>(now) * 3; }}, 7};
  std::deque<Event> model;
  std::uint64_t seq = 0;
  std::uint32_t x = 12345;
  const auto next = [&] {
    x = x * 1103515245U + 12345U;
    return (x >> 8) & 0xFFFF;
  };
  for (int i = 0; i < 3000; ++i) {
    now = static_cast<std::uint64_t>(i) * 5;
    // mostly short texts, sometimes long ones (the buffer grows), then short again (it shrinks)
    const std::size_t len = (i / 500) % 2 == 1 && next() % 4 == 0 ? 300 + next() % 2000 : next() % 40;
    const std::string text(len, static_cast<char>('a' + i % 26));
    const std::string peer = next() % 3 == 0 ? "" : "10.0.0." + std::to_string(i % 250) + ":" + std::to_string(i);
    const Flags flags{.overlong = i % 5 == 0, .ignored = i % 7 == 0, .polling = i % 3 == 0};
    const auto channel = static_cast<Channel>(i % k_channel_count);
    EXPECT_EQ(ring.record(channel, Dir::tx, text, static_cast<std::uint64_t>(i), peer, flags), ++seq);
    model.push_back(Event{seq, now, static_cast<std::int64_t>(now) * 3, channel, Dir::tx, static_cast<std::uint64_t>(i),
                          peer, text, flags});
    if (model.size() > 7) model.pop_front();
    const std::uint64_t from = seq > 9 ? seq - 9 : 0;
    const auto r = ring.query(since(from));
    ASSERT_EQ(r.events.size(), model.size()) << i;
    for (std::size_t k = 0; k < model.size(); ++k) {
      const Event& a = r.events[k];
      const Event& b = model[k];
      ASSERT_EQ(a.seq, b.seq) << i;
      ASSERT_EQ(a.time_ms, b.time_ms);
      ASSERT_EQ(a.wall_ms, b.wall_ms);
      ASSERT_EQ(a.channel, b.channel);
      ASSERT_EQ(a.conn, b.conn);
      ASSERT_EQ(a.peer, b.peer) << i;
      ASSERT_EQ(a.text, b.text) << i;
      ASSERT_EQ(a.flags.overlong, b.flags.overlong);
      ASSERT_EQ(a.flags.ignored, b.flags.ignored);
      ASSERT_EQ(a.flags.polling, b.flags.polling);
    }
    const std::uint64_t oldest = model.front().seq;
    const std::uint64_t wanted = std::max<std::uint64_t>(from, 1);
    ASSERT_EQ(r.dropped, wanted < oldest ? oldest - wanted : 0) << i;
  }
}

// Events without any bytes (no peer, empty text) before and after the first byte: no byte buffer
// is needed for them, and they read back empty.
TEST(TraceRing, EventsWithoutBytes) {
  Fixture f;
  EXPECT_EQ(f.ring.record(Channel::udp, Dir::rx, ""), 1U);
  EXPECT_EQ(f.ring.text_capacity(), 0U);
  f.ring.record(Channel::refgo, Dir::rx, "TP\r", 1, "127.0.0.1:5000");
  f.ring.record(Channel::udp, Dir::rx, "");
  const auto r = f.ring.query({});
  ASSERT_EQ(r.events.size(), 3U);
  EXPECT_EQ(r.events[0].text, "");
  EXPECT_EQ(r.events[0].peer, "");
  EXPECT_EQ(r.events[1].text, "TP\r");
  EXPECT_EQ(r.events[2].text, "");
}

// What the ring's texts cost follows what it holds: a burst of long texts grows the byte buffer,
// and once they have left the ring it shrinks again (within 4× of the bytes held).
TEST(TraceRing, TextMemoryFollowsWhatTheRingHolds) {
  Ring ring{Ring::Clocks{}, 100};
  for (int i = 0; i < 100; ++i) ring.record(Channel::http, Dir::rx, std::string(8000, 'x'));
  EXPECT_EQ(ring.text_bytes(), 800000U);
  EXPECT_GE(ring.text_capacity(), 800000U);
  for (int i = 0; i < 100; ++i) ring.record(Channel::drive, Dir::event, "TargetReached mode 1");
  EXPECT_EQ(ring.text_bytes(), 2000U);
  EXPECT_LE(ring.text_capacity(), 4 * 2000U + ByteFifo::k_min_capacity);
  EXPECT_EQ(ring.query({}).events.back().text, "TargetReached mode 1");
}

// A full ring of a moving drive's events (~30 characters, no peer): about 70 bytes an event.
TEST(TraceRing, AFullRingOfDriveEventsIsCompact) {
  Ring ring{Ring::Clocks{}};
  for (std::size_t i = 0; i < 3 * Ring::k_default_capacity; ++i) {
    ring.record(Channel::drive, Dir::event, "StatuswordChanged 1127h -> 0127h");
  }
  EXPECT_EQ(ring.size(), Ring::k_default_capacity);
  EXPECT_EQ(ring.text_bytes(), 32 * Ring::k_default_capacity);
  EXPECT_LE(ring.text_capacity(), 2 * ring.text_bytes());
}

// A listener that records into the ring itself still sees each event whole: the inner event does
// not overwrite the one the outer call is looking at.
TEST(TraceRing, AListenerThatRecordsSeesBothEventsWhole) {
  Fixture f;
  std::vector<std::string> seen;
  f.ring.set_listener([&](const Event& e) {
    if (e.text == "outer") f.ring.record(Channel::api, Dir::event, "inner");
    seen.push_back(e.text);
  });
  f.ring.record(Channel::drive, Dir::event, "outer");
  EXPECT_EQ(seen, (std::vector<std::string>{"inner", "outer"}));
}

TEST(TraceChannels, Parse) {
  EXPECT_EQ(parse_channels(""), ChannelSet{});
  const auto s = parse_channels("refgo,udp");
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->contains(Channel::refgo));
  EXPECT_TRUE(s->contains(Channel::udp));
  EXPECT_FALSE(s->contains(Channel::slcan));
  EXPECT_FALSE(parse_channels("refgo,bogus"));
  // the master lint's channel (docs/lint.md) is one of "all"
  EXPECT_EQ(channel_from_string("lint"), Channel::lint);
  EXPECT_TRUE(ChannelSet{}.contains(Channel::lint));
  EXPECT_FALSE(parse_channels("refgo,"));
  for (std::size_t i = 0; i < k_channel_count; ++i) {
    const auto c = static_cast<Channel>(i);
    EXPECT_EQ(channel_from_string(to_string(c)), c);
  }
}

// Unix ms → ISO 8601 UTC, against dates computed independently (Python's datetime), leap days and
// century rules included; negative = unknown.
TEST(TraceWall, FormatUtcMs) {
  const std::vector<std::pair<std::int64_t, std::string>> cases{
      {0, "1970-01-01T00:00:00.000Z"},
      {951868799999, "2000-02-29T23:59:59.999Z"},
      {951868800000, "2000-03-01T00:00:00.000Z"},
      {1700000000123, "2023-11-14T22:13:20.123Z"},
      {1735646400005, "2024-12-31T12:00:00.005Z"},
      {4107546123045, "2100-03-01T01:02:03.045Z"},
      {253402300799999, "9999-12-31T23:59:59.999Z"},
      {-1, ""},
  };
  for (const auto& [ms, text] : cases) EXPECT_EQ(format_utc_ms(ms), text) << ms;
}

TEST(TraceHex, Bytes) { EXPECT_EQ(hex_bytes(std::string("\x00\x1f\xab", 3)), "001FAB"); }

}  // namespace
}  // namespace mcemu::trace
