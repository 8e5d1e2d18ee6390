// The scope sampler of web.md §5.3/§8.7: 5 ms of drive time per sample, a 60 s ring, ?sinceMs and
// the "since the previous call" blocks of the WebSocket scope message.
#include "device/scope.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <random>

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

// What the ring means, kept plainly: every sample of the window, one by one.
class PlainScope {
 public:
  void add_run(std::uint64_t t, std::uint64_t count, const ScopeSample& s) {
    if (count == 0) return;
    if (count > Scope::k_capacity) {
      t += (count - Scope::k_capacity) * Scope::k_sample_ms;
      count = Scope::k_capacity;
    }
    if (samples_.empty() || t != first_ + samples_.size() * Scope::k_sample_ms) {
      samples_.clear();
      first_ = t;
      if (t < next_new_) next_new_ = t;
    }
    samples_.insert(samples_.end(), count, s);
    while (samples_.size() > Scope::k_capacity) {
      samples_.pop_front();
      first_ += Scope::k_sample_ms;
    }
  }
  std::size_t size() const { return samples_.size(); }
  device::ScopeBlock since_ms(std::uint64_t t) const {
    device::ScopeBlock b;
    std::size_t from = 0;
    if (!samples_.empty() && t > first_) {
      from = std::min<std::size_t>((t - first_ + Scope::k_sample_ms - 1) / Scope::k_sample_ms, samples_.size());
    }
    b.t0 = samples_.empty() ? 0 : first_ + from * Scope::k_sample_ms;
    b.samples.assign(samples_.begin() + static_cast<std::ptrdiff_t>(from), samples_.end());
    return b;
  }
  device::ScopeBlock take_new() {
    auto b = since_ms(next_new_);
    if (!samples_.empty()) next_new_ = first_ + samples_.size() * Scope::k_sample_ms;
    return b;
  }

 private:
  std::deque<ScopeSample> samples_;
  std::uint64_t first_ = 0;
  std::uint64_t next_new_ = 0;
};

// The encoded ring reads back what was added: random walks with small and extreme steps, equal
// samples, long runs, gaps and time going back, read at random times.
TEST(Scope, EncodedRingReadsBackEverySample) {
  std::mt19937 rng(26);
  const auto pick = [&](std::uint32_t n) { return std::uniform_int_distribution<std::uint32_t>(0, n - 1)(rng); };
  const auto step = [&](std::int32_t v) -> std::int32_t {
    switch (pick(6)) {
      case 0: return v;
      case 1: return pick(2) ? INT32_MAX : INT32_MIN;
      case 2: return static_cast<std::int32_t>(rng());
      default: return static_cast<std::int32_t>(static_cast<std::int64_t>(v) + pick(4001) - 2000);
    }
  };
  for (int round = 0; round < 10; ++round) {
    Scope scope;
    PlainScope plain;
    ScopeSample s{};
    std::uint64_t t = 1000;
    for (int i = 0; i < 30000; ++i) {
      if (pick(3) != 0)
        s = ScopeSample{step(s.pos), step(s.vel), step(s.cur), step(s.target),
                        static_cast<std::uint16_t>(pick(4) == 0 ? rng() : s.sw)};
      std::uint64_t count = 1;
      if (pick(50) == 0) count = pick(3) == 0 ? pick(30000) : pick(40);
      if (pick(2000) == 0) t = pick(2) ? t + 5 * (1 + pick(10)) : t / 2 / 5 * 5;  // a gap, or back
      scope.add_run(t, count, s);
      plain.add_run(t, count, s);
      t += 5 * count;
      ASSERT_EQ(scope.size(), plain.size());
      if (pick(500) == 0 || i == 29999) {
        const std::uint64_t since = pick(2) ? 0 : t - 5 * pick(13000);
        const auto a = scope.since_ms(since);
        const auto b = plain.since_ms(since);
        ASSERT_EQ(a.t0, b.t0) << "round " << round << " step " << i;
        ASSERT_EQ(a.samples, b.samples) << "round " << round << " step " << i;
      }
      if (pick(300) == 0) {
        const auto a = scope.take_new();
        const auto b = plain.take_new();
        ASSERT_EQ(a.t0, b.t0);
        ASSERT_EQ(a.samples, b.samples);
      }
    }
  }
}

// A moving drive's window (every sample differs a little from the one before) takes a few bytes a
// sample, not the 24 of a plain run.
TEST(Scope, MovingWindowTakesFewBytesPerSample) {
  Scope s;
  std::int32_t pos = 0;
  std::int32_t vel = 0;
  for (std::uint64_t t = 0; t < 2 * Scope::k_window_ms; t += 5) {
    vel = std::min(vel + 20, 4000);  // accelerating, then constant
    pos += vel / 200;
    s.add(t, ScopeSample{pos, vel, 300 + static_cast<std::int32_t>(t % 7), 100000, 0x1237});
  }
  EXPECT_EQ(s.size(), Scope::k_capacity);
  EXPECT_LE(s.encoded_bytes(), 6 * Scope::k_capacity);
  EXPECT_EQ(s.since_ms(0).samples.back().pos, pos);
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
