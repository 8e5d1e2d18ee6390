// The engine as a whole (lint/engine.cpp): mode off, the rate limit, drive time across power
// cycles, reset, and a randomized property test: random observation sequences never crash and the
// counts always agree with what the sink saw.
#include <gtest/gtest.h>

#include <random>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

void ignored_command(Lint& l, Ms t) {
  l.drive_at(t, 0x0040, 1);
  l.engine.observe(write(t, 0x6040, 0x000F, 0x0040, 1));
}

TEST(Engine, ModeOffDropsEverything) {
  Config c;
  c.mode = Mode::off;
  Lint l(c);
  ignored_command(l, 1);
  EXPECT_TRUE(l.found.empty());
  EXPECT_EQ(l.engine.counts(RuleId::cia402_command_ignored).occurrences, 0U);
  EXPECT_EQ(l.engine.view().statusword, 0U);  // nothing tracked either
}

TEST(Engine, RuleOffIsNeitherReportedNorCounted) {
  Config c;
  c.severity[static_cast<std::size_t>(RuleId::cia402_command_ignored)].reset();
  Lint l(c);
  ignored_command(l, 1);
  EXPECT_TRUE(l.found.empty());
  EXPECT_EQ(l.engine.counts(RuleId::cia402_command_ignored).occurrences, 0U);
}

TEST(Engine, RateLimitPerRuleAndSecondOfDriveTime) {
  Config c;
  c.findings_per_second = 3;
  Lint l(c);
  for (int i = 0; i < 10; ++i) ignored_command(l, 2000 + static_cast<Ms>(i));
  EXPECT_EQ(l.found.size(), 3U);
  const RuleCount& n = l.engine.counts(RuleId::cia402_command_ignored);
  EXPECT_EQ(n.occurrences, 10U);
  EXPECT_EQ(n.reported, 3U);
  EXPECT_EQ(n.suppressed, 7U);
  EXPECT_EQ(n.last_time_ms, 2009U);
  ignored_command(l, 3000);  // the next second
  EXPECT_EQ(l.found.size(), 4U);
}

TEST(Engine, NoRateLimitWithZero) {
  Config c;
  c.findings_per_second = 0;
  Lint l(c);
  for (int i = 0; i < 50; ++i) ignored_command(l, 5);
  EXPECT_EQ(l.found.size(), 50U);
}

TEST(Engine, StrictCountsWarningsAsFailures) {
  Config c;
  c.severity[static_cast<std::size_t>(RuleId::refgo_faster_than_drive)] = Severity::error;
  Lint l(c);
  ignored_command(l, 1);  // warn
  l.engine.observe(ProtocolRequest{10, Link::refgo, 1, 0, true});
  l.engine.observe(ProtocolReply{10, Link::refgo, 1, ReplyKind::response});
  l.engine.observe(ProtocolRequest{11, Link::refgo, 1, 0, true});  // error (configured)
  EXPECT_EQ(l.engine.total(Severity::warn), 1U);
  EXPECT_EQ(l.engine.total(Severity::error), 1U);
  EXPECT_EQ(l.engine.failing(), 1U);
  c.mode = Mode::strict;
  l.engine.configure(c);
  EXPECT_EQ(l.engine.failing(), 2U);
}

TEST(Engine, ResetClearsCountsAndFindingsButNotTheView) {
  Lint l;
  ignored_command(l, 1);
  l.engine.reset();
  EXPECT_EQ(l.engine.counts(RuleId::cia402_command_ignored).occurrences, 0U);
  EXPECT_TRUE(l.engine.recent().empty());
  EXPECT_EQ(l.engine.failing(), 0U);
  EXPECT_EQ(l.engine.view().statusword, 0x0040U);
  l.engine.observe(write(2, 0x6040, 0x000F, 0x0040, 1));
  ASSERT_EQ(l.engine.recent().size(), 1U);
  EXPECT_EQ(l.engine.recent()[0].seq, 2U);  // sequence numbers go on
}

TEST(Engine, PowerOnResetsTheViewOfTheDrive) {
  Lint l;
  l.drive_at(0, 0x0027, 3);
  l.engine.observe(write(1, 0x60FF, 100, 0x0127, 3));
  l.engine.observe(PowerOn{0, 0x0000, 0x0000, 0, 0});
  EXPECT_EQ(l.engine.view().statusword, 0U);
  EXPECT_EQ(l.engine.view().target_velocity, 0);
  EXPECT_EQ(l.engine.view().mode_display, 0);
}

TEST(Engine, RateLimitWindowContinuesAcrossAPowerCycle) {
  Config c;
  c.findings_per_second = 1;
  Lint l(c);
  ignored_command(l, 1500);
  l.engine.observe(PowerOn{0, 0, 0, 0, 0});
  ignored_command(l, 100);  // drive time 100 = lint time 1600: the same second
  EXPECT_EQ(l.found.size(), 1U);
  EXPECT_EQ(l.engine.counts(RuleId::cia402_command_ignored).suppressed, 1U);
}

TEST(Engine, RecentRingKeepsTheNewest) {
  Config c;
  c.findings_per_second = 0;
  c.recent_capacity = 4;
  Lint l(c);
  for (Ms t = 1; t <= 10; ++t) ignored_command(l, t);
  const auto r = l.engine.recent();
  ASSERT_EQ(r.size(), 4U);
  EXPECT_EQ(r.front().seq, 7U);
  EXPECT_EQ(r.back().seq, 10U);
  c.recent_capacity = 2;
  l.engine.configure(c);
  ASSERT_EQ(l.engine.recent().size(), 2U);
  EXPECT_EQ(l.engine.recent().front().seq, 9U);
}

// ---- randomized property test

class Random {
 public:
  explicit Random(std::uint32_t seed) : g_(seed) {}
  std::uint64_t below(std::uint64_t n) { return std::uniform_int_distribution<std::uint64_t>(0, n - 1)(g_); }
  template <typename T>
  T pick(std::initializer_list<T> v) {
    return *(v.begin() + below(v.size()));
  }

 private:
  std::mt19937 g_;
};

void feed_random(Engine& e, Random& r, Ms& t) {
  // time mostly moves forward in small steps, sometimes restarts (power cycle)
  t += r.below(5) == 0 ? r.below(3000) : r.below(3);
  const std::uint16_t sw = r.pick<std::uint16_t>({0x0000, 0x0040, 0x0021, 0x0023, 0x0027, 0x0127, 0x1127, 0x0007,
                                                  0x000F, 0x0008, 0x0427, static_cast<std::uint16_t>(r.below(65536))});
  const auto origin = static_cast<od::Origin>(r.below(5));
  const Conn conn = r.below(40);
  switch (r.below(13)) {
    case 0:
    case 1:
    case 2: {
      OdWrite w;
      w.time = t;
      w.conn = conn;
      w.origin = origin;
      w.index = r.pick<std::uint16_t>({0x6040, 0x6060, 0x607A, 0x60FF, 0x6098, 0x1010, 0x1011, 0x3010, 0x2000});
      w.sub = static_cast<std::uint8_t>(r.below(4));
      w.value = r.pick<std::int64_t>({0, 6, 7, 0x0F, 0x1F, 0x3F, 0x0B, 0x1B, 0x80, 0x86, 0x65766173, 0x64616F6C, -5,
                                      static_cast<std::int64_t>(r.below(1u << 31))});
      w.result = r.pick<od::AbortCode>({od::AbortCode::none, od::AbortCode::pending, od::AbortCode::invalid_value});
      w.statusword_after = sw;
      w.mode_after = r.pick<std::int8_t>({0, 1, 3, 6});
      w.helper = r.below(4) == 0;
      e.observe(w);
      break;
    }
    case 3: {
      const core::Event ev = r.below(2) ? core::Event{core::StatuswordChanged{0, sw}}
                                        : core::Event{core::ModeDisplayChanged{static_cast<std::int8_t>(r.below(7))}};
      e.observe(CoreEvent{t, ev});
      break;
    }
    case 4:
      t = r.below(100);
      e.observe(PowerOn{t, 0, 0, static_cast<std::int8_t>(r.below(4)), static_cast<std::int64_t>(r.below(3))});
      break;
    case 5:
      e.observe(NmtChange{t, Nmt::operational,
                          r.pick<Nmt>({Nmt::initialising, Nmt::stopped, Nmt::operational, Nmt::pre_operational})});
      break;
    case 6: {
      CanRequest c;
      c.time = t;
      c.conn = conn;
      c.kind = static_cast<CanKind>(r.below(6));
      c.byte0 = static_cast<std::uint8_t>(r.below(256));
      c.rpdo = static_cast<std::uint8_t>(1 + r.below(4));
      c.motion = r.below(2) != 0;
      c.life_time_ms = static_cast<std::uint32_t>(r.below(2) * 300);
      e.observe(c);
      break;
    }
    case 7: e.observe(SdoAnswer{t, static_cast<std::uint8_t>(r.below(256))}); break;
    case 8:
      e.observe(PdoMappingWrite{t, conn, origin, static_cast<std::uint16_t>(0x1600 + r.below(0x600)),
                                static_cast<std::uint8_t>(r.below(9)), r.below(2) != 0, od::AbortCode::none});
      break;
    case 9:
      e.observe(ProtocolRequest{t, r.below(2) ? Link::refgo : Link::faulhaber, conn, r.below(4), r.below(5) != 0});
      break;
    case 10:
      e.observe(ProtocolReply{t, r.below(2) ? Link::refgo : Link::faulhaber, r.below(3) ? conn : 0,
                              static_cast<ReplyKind>(r.below(3))});
      break;
    case 11:
      if (r.below(2)) {
        e.observe(ScriptLoop{t, r.below(2) ? ScriptKind::code : ScriptKind::basic,
                             static_cast<std::uint32_t>(r.below(3000))});
      } else {
        e.observe(FlashWrite{t, conn, origin, static_cast<FlashKind>(r.below(4))});
      }
      break;
    default: e.observe(ConnectionClosed{conn}); break;
  }
}

TEST(EngineProperty, RandomSequencesKeepTheCountsConsistent) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    Config c;
    c.findings_per_second = 1 + seed % 4;
    c.recent_capacity = 1 + seed * 3;
    c.max_stores_per_hour = 1 + seed % 5;
    c.timing = seed % 3 != 0;
    for (std::size_t i = 0; i < k_rule_count; ++i) {
      if ((i + seed) % 7 == 0) c.severity[i].reset();
      if ((i + seed) % 5 == 0) c.severity[i] = Severity::error;
    }
    std::uint64_t sunk = 0;
    std::uint64_t last_seq = 0;
    bool ordered = true;
    Engine e(c, [&](const Finding& f) {
      ++sunk;
      ordered = ordered && f.seq == last_seq + 1;
      last_seq = f.seq;
    });
    Random r(seed);
    Ms t = 0;
    for (int i = 0; i < 20000; ++i) feed_random(e, r, t);

    std::uint64_t reported = 0, occurrences = 0;
    for (const auto& rule : rule_table()) {
      const RuleCount& n = e.counts(rule.id);
      EXPECT_EQ(n.occurrences, n.reported + n.suppressed) << rule.name;
      if (!c.rule_on(rule.id) || (rule.timing && !c.timing)) {
        EXPECT_EQ(n.occurrences, 0U) << rule.name;
      }
      reported += n.reported;
      occurrences += n.occurrences;
    }
    EXPECT_EQ(reported, sunk) << "seed " << seed;
    EXPECT_TRUE(ordered) << "seed " << seed;
    EXPECT_EQ(e.total(Severity::info) + e.total(Severity::warn) + e.total(Severity::error), occurrences);
    EXPECT_LE(e.recent().size(), c.recent_capacity);
    EXPECT_EQ(e.recent().size(), std::min<std::uint64_t>(sunk, c.recent_capacity));
    EXPECT_GT(sunk, 0U) << "seed " << seed << ": the sequence should trigger something";
  }
}

}  // namespace
}  // namespace mcemu::lint::test
