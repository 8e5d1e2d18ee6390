// The JSON body of GET /api/v1/lint (lint/json_view.cpp).
#include "lint/json_view.hpp"

#include <gtest/gtest.h>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

TEST(LintJson, RulesTotalsAndRecentFindings) {
  Config c;
  c.severity[static_cast<std::size_t>(RuleId::script_busy_loop)].reset();
  c.findings_per_second = 1;
  Lint l(c);
  l.drive_at(10, 0x0040, 1);
  l.engine.observe(write(10, 0x6040, 0x000F, 0x0040, 1, od::Origin::web, 5));
  l.engine.observe(write(11, 0x6040, 0x000F, 0x0040, 1, od::Origin::web, 5));  // suppressed

  const auto j = lint_json(l.engine);
  EXPECT_EQ(j["mode"], "warn");
  EXPECT_EQ(j["timing"], true);
  EXPECT_EQ(j["totals"]["warn"], 2);
  EXPECT_EQ(j["totals"]["error"], 0);
  EXPECT_EQ(j["totals"]["suppressed"], 1);
  EXPECT_EQ(j["totals"]["failing"], 0);
  ASSERT_EQ(j["rules"].size(), k_rule_count);
  for (const auto& row : j["rules"]) {
    for (const char* key : {"id", "family", "severity", "default_severity", "timing", "summary", "advice", "reference",
                            "count", "reported", "suppressed", "last_time_ms"}) {
      EXPECT_TRUE(row.contains(key)) << key;
    }
    if (row["id"] == "cia402.command_ignored") {
      EXPECT_EQ(row["count"], 2);
      EXPECT_EQ(row["reported"], 1);
      EXPECT_EQ(row["suppressed"], 1);
      EXPECT_EQ(row["last_time_ms"], 11);
    } else {
      EXPECT_TRUE(row["last_time_ms"].is_null());
    }
    if (row["id"] == "script.busy_loop") {
      EXPECT_EQ(row["severity"], "off");
      EXPECT_EQ(row["default_severity"], "warn");
    }
  }
  ASSERT_EQ(j["recent"].size(), 1U);
  const auto& f = j["recent"][0];
  EXPECT_EQ(f["seq"], 1);
  EXPECT_EQ(f["rule"], "cia402.command_ignored");
  EXPECT_EQ(f["severity"], "warn");
  EXPECT_EQ(f["time_ms"], 10);
  EXPECT_EQ(f["conn"], 5);
  EXPECT_EQ(f["origin"], "web");
  EXPECT_EQ(f["detail"], "controlword 0x000F (Enable operation) in Switch on disabled is ignored");
  EXPECT_EQ(f["reference"], info(RuleId::cia402_command_ignored).reference);
  EXPECT_EQ(f["text"], finding_text(l.engine.recent()[0]));
  EXPECT_NO_THROW((void)j.dump());
}

TEST(LintJson, TimingRulesShowOffWithTimingOff) {
  Config c;
  c.timing = false;
  Lint l(c);
  const auto j = lint_json(l.engine);
  for (const auto& row : j["rules"]) {
    if (row["timing"] == true) {
      EXPECT_EQ(row["severity"], "off") << row["id"];
    }
  }
}

}  // namespace
}  // namespace mcemu::lint::test
