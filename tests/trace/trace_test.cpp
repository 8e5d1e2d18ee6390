// The trace ring (web.md §8.6): sequence numbers, capacity, `since`/`limit`/channel queries,
// `dropped` counting, channel parsing.
#include "trace/trace.hpp"

#include <gtest/gtest.h>

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
