// The scope sampler of web.md §5.3/§8.7: 5 ms of drive time per sample, a 60 s ring, ?sinceMs and
// the "since the previous call" blocks of the WebSocket scope message.
#include "device/scope.hpp"

#include <gtest/gtest.h>

#include "tests/web/api_fixture.hpp"

namespace mcemu::web::api {
namespace {

using device::Scope;
using device::scope_message;
using device::ScopeSample;

using nlohmann::json;

ScopeSample sample(std::int32_t pos) {
  return ScopeSample{pos, pos + 1, pos + 2, pos + 3, static_cast<std::uint16_t>(pos)};
}

TEST(Scope, SinceMsStartsAtTheFirstSampleTimeAtOrAfterT) {
  Scope s;
  for (std::uint64_t t = 100; t <= 200; t += 5) s.add(t, sample(static_cast<std::int32_t>(t)));
  struct Case {
    std::uint64_t since, t0;
    std::size_t count;
  };
  for (const auto& c : {Case{0, 100, 21}, Case{100, 100, 21}, Case{101, 105, 20}, Case{104, 105, 20},
                        Case{105, 105, 20}, Case{200, 200, 1}, Case{201, 205, 0}, Case{99999, 205, 0}}) {
    const auto b = s.since_ms(c.since);
    EXPECT_EQ(b.t0, c.t0) << c.since;
    EXPECT_EQ(b.samples.size(), c.count) << c.since;
    if (!b.samples.empty()) {
      EXPECT_EQ(b.samples.front().pos, static_cast<std::int32_t>(c.t0)) << c.since;
    }
  }
}

// A quiet stretch adds its equal samples as one run (issue 26: an idle fleet woken after an hour
// must not push 12 000 samples per drive); what is read back is the same as sample by sample.
TEST(Scope, RunOfEqualSamplesReadsLikeSingleSamples) {
  struct Case {
    std::uint64_t before, run;  // samples added one by one, then as one run of equal samples
  };
  for (const auto& c : {Case{0, 1}, Case{3, 10}, Case{100, Scope::k_capacity}, Case{20, Scope::k_capacity + 7},
                        Case{Scope::k_capacity, 5}, Case{Scope::k_capacity - 1, 3 * Scope::k_capacity}}) {
    Scope one;
    Scope run;
    std::uint64_t t = 1000;
    for (std::uint64_t i = 0; i < c.before; ++i, t += 5) {
      one.add(t, sample(static_cast<std::int32_t>(i)));
      run.add(t, sample(static_cast<std::int32_t>(i)));
    }
    run.add_run(t, c.run, sample(-7));
    for (std::uint64_t i = 0; i < c.run; ++i, t += 5) one.add(t, sample(-7));
    EXPECT_EQ(run.size(), one.size()) << c.before << "+" << c.run;
    for (std::uint64_t since : {std::uint64_t{0}, std::uint64_t{1000}, t - 300, t - 5, t}) {
      const auto a = one.since_ms(since);
      const auto b = run.since_ms(since);
      EXPECT_EQ(a.t0, b.t0) << since;
      EXPECT_EQ(a.samples, b.samples) << since;
    }
    EXPECT_EQ(run.take_new().samples, one.take_new().samples);
  }
}

TEST(Scope, RingHoldsSixtySeconds) {
  Scope s;
  for (std::uint64_t t = 0; t <= 70000; t += 5) s.add(t, sample(static_cast<std::int32_t>(t)));
  EXPECT_EQ(s.size(), Scope::k_capacity);
  EXPECT_EQ(Scope::k_capacity, 12000u);
  const auto b = s.since_ms(0);
  EXPECT_EQ(b.t0, 70000 - 5 * (12000 - 1));
  EXPECT_EQ(b.samples.back().pos, 70000);
}

TEST(Scope, TakeNewReturnsEachSampleOnce) {
  Scope s;
  EXPECT_TRUE(s.take_new().samples.empty());
  for (std::uint64_t t = 0; t < 50; t += 5) s.add(t, sample(static_cast<std::int32_t>(t)));
  auto b = s.take_new();
  EXPECT_EQ(b.t0, 0u);
  EXPECT_EQ(b.samples.size(), 10u);
  b = s.take_new();
  EXPECT_TRUE(b.samples.empty());
  EXPECT_EQ(b.t0, 50u) << "an empty block names the next sample time";
  s.add(50, sample(50));
  s.add(55, sample(55));
  b = s.take_new();
  EXPECT_EQ(b.t0, 50u);
  ASSERT_EQ(b.samples.size(), 2u);
  EXPECT_EQ(b.samples[1].pos, 55);
}

TEST(Scope, GapOrTimeGoingBackStartsAnew) {
  Scope s;
  for (std::uint64_t t = 1000; t <= 1100; t += 5) s.add(t, sample(1));
  (void)s.take_new();
  s.add(20, sample(2));  // a power cycle restarted drive time
  EXPECT_EQ(s.size(), 1u);
  auto b = s.take_new();
  EXPECT_EQ(b.t0, 20u);
  EXPECT_EQ(b.samples.size(), 1u) << "the new samples are not hidden behind the old time";
  s.add(40, sample(3));  // a gap: samples stay contiguous
  EXPECT_EQ(s.size(), 1u);
  EXPECT_EQ(s.since_ms(0).t0, 40u);
}

TEST(Scope, SamplesTheFiveObjectsEveryFiveMsOfDriveTime) {
  testing::ApiFixture f;
  f.step(3);
  f.refgo("PWC");
  f.step(10);
  f.refgo("G100000");
  const auto start = f.core.time_ms();
  f.step(200);
  f.step((5 - f.core.time_ms() % 5) % 5);  // end on a sample time
  const json j = f.get("/api/v1/scope?sinceMs=" + std::to_string(start));
  EXPECT_EQ(j["sampleMs"], 5);
  EXPECT_EQ(j["t0"].get<std::uint64_t>() % 5, 0u);
  EXPECT_GE(j["t0"].get<std::uint64_t>(), start);
  const std::uint64_t end = f.core.time_ms();
  const std::size_t expected = end / 5 - (start + 4) / 5 + 1;  // the multiples of 5 in [start, end]
  EXPECT_EQ(j["pos"].size(), expected);
  for (const char* k : {"vel", "cur", "target", "sw"}) EXPECT_EQ(j[k].size(), expected) << k;
  EXPECT_EQ(j["target"].back(), 100000);
  EXPECT_EQ(j["pos"].back(), f.n(0x6064, 0));
  EXPECT_EQ(j["sw"].back(), f.n(0x6041, 0));
  EXPECT_GT(j["pos"].back().get<int>(), j["pos"].front().get<int>()) << "the move shows";
  EXPECT_GT(j["vel"].back().get<int>(), 0);
  EXPECT_EQ(f.call("GET", "/api/v1/scope?sinceMs=-1").status, 400);
  EXPECT_EQ(f.call("GET", "/api/v1/scope?sinceMs=abc").status, 400);
  EXPECT_EQ(f.call("GET", "/api/v1/scope?since=1").status, 400) << "unknown parameter";
}

TEST(Scope, WebSocketMessage) {
  Scope s;
  s.add(10, ScopeSample{1, 2, 3, 4, 0x427});
  const json m = json::parse(scope_message(s.take_new()));
  EXPECT_EQ(m, (json{{"type", "scope"},
                     {"sampleMs", 5},
                     {"t0", 10},
                     {"pos", {1}},
                     {"vel", {2}},
                     {"cur", {3}},
                     {"target", {4}},
                     {"sw", {0x427}}}));
}

}  // namespace
}  // namespace mcemu::web::api
