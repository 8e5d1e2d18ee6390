// The rule table (lint/rules.cpp): complete, unique ids, every row explained and referenced.
#include "lint/rules.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace mcemu::lint {
namespace {

TEST(RuleTable, EveryRowIsCompleteAndNamedUniquely) {
  std::set<std::string_view> names;
  for (const auto& r : rule_table()) {
    EXPECT_EQ(&info(r.id), &r);
    EXPECT_TRUE(names.insert(r.name).second) << r.name;
    EXPECT_EQ(r.name.substr(0, r.family.size()), r.family) << r.name;
    EXPECT_EQ(r.name[r.family.size()], '.') << r.name;
    EXPECT_FALSE(r.summary.empty()) << r.name;
    EXPECT_FALSE(r.advice.empty()) << r.name;
    // every rule rests on a section of docs/reference (checked by tools/lint_citations.py there)
    EXPECT_NE(r.reference.find(".md §"), std::string_view::npos) << r.name;
    EXPECT_EQ(rule_from_name(r.name), r.id);
  }
  EXPECT_EQ(names.size(), k_rule_count);
  EXPECT_EQ(rule_from_name("cia402.nope"), std::nullopt);
}

TEST(RuleTable, Severities) {
  for (auto s : {Severity::info, Severity::warn, Severity::error}) EXPECT_EQ(severity_from_string(to_string(s)), s);
  EXPECT_EQ(severity_from_string("off"), std::nullopt);
  EXPECT_EQ(severity_from_string("WARN"), std::nullopt);
}

}  // namespace
}  // namespace mcemu::lint
