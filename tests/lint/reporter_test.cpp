// The reporting half (lint/reporter.cpp): the finding text, counting, the rate limit.
#include "lint/reporter.hpp"

#include <gtest/gtest.h>

namespace mcemu::lint {
namespace {

TEST(FindingText, NamesRuleSeverityDetailAdviceAndReference) {
  Finding f;
  f.rule = RuleId::canopen_sdo_while_stopped;
  f.severity = Severity::error;
  f.detail = "SDO request (byte 0 = 0x40) to a STOPPED node";
  EXPECT_EQ(finding_text(f),
            "canopen.sdo_while_stopped error: SDO request (byte 0 = 0x40) to a STOPPED node — send NMT enter "
            "pre-operational (0x80) or start (0x01) before using SDO [slcan-canopen.md §4.3; CiA 301 NMT state "
            "machine]");
}

TEST(Reporter, DetailIsBuiltOnlyForReportedFindings) {
  Config c;
  c.findings_per_second = 1;
  Reporter rep(c);
  int built = 0;
  const At at{10, 10, 2, "sdo"};
  for (int i = 0; i < 5; ++i) {
    rep.fire(RuleId::canopen_sdo_overlap, at, [&] {
      ++built;
      return std::string("x");
    });
  }
  EXPECT_EQ(built, 1);
  EXPECT_EQ(rep.counts(RuleId::canopen_sdo_overlap).suppressed, 4U);
  EXPECT_EQ(rep.total(Severity::warn), 5U);
}

TEST(Reporter, OffRuleAndTimingRuleWithTimingOff) {
  Config c;
  c.timing = false;
  c.severity[static_cast<std::size_t>(RuleId::canopen_sdo_overlap)].reset();
  Reporter rep(c);
  EXPECT_FALSE(rep.on(RuleId::canopen_sdo_overlap));
  EXPECT_FALSE(rep.on(RuleId::storage_store_rate));  // timing rule
  EXPECT_TRUE(rep.on(RuleId::storage_store_while_moving));
  rep.fire(RuleId::storage_store_rate, At{}, [] { return std::string(); });
  EXPECT_EQ(rep.counts(RuleId::storage_store_rate).occurrences, 0U);
}

TEST(Reporter, SinkSeesEachReportedFindingWithItsFields) {
  Config c;
  Reporter rep(c);
  std::vector<Finding> seen;
  rep.set_sink([&](const Finding& f) { seen.push_back(f); });
  rep.fire(RuleId::script_busy_loop, At{77, 1077, 0, "basic"}, [] { return std::string("loop"); });
  ASSERT_EQ(seen.size(), 1U);
  EXPECT_EQ(seen[0].seq, 1U);
  EXPECT_EQ(seen[0].time_ms, 77U);  // drive time, not the lint's continued time
  EXPECT_EQ(seen[0].origin, "basic");
  EXPECT_EQ(seen[0].detail, "loop");
  EXPECT_EQ(seen[0].severity, Severity::warn);
}

}  // namespace
}  // namespace mcemu::lint
