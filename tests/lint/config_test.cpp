// The "lint" config section (lint/config.cpp): parsing, errors naming the key, the JSON form.
#include "lint/config.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

namespace mcemu::lint {
namespace {

using nlohmann::json;

TEST(LintConfig, DefaultsAreTheTable) {
  const Config c = config_from_json(json::object());
  EXPECT_EQ(c.mode, Mode::warn);
  EXPECT_TRUE(c.timing);
  for (const auto& r : rule_table()) EXPECT_EQ(c.severity[static_cast<std::size_t>(r.id)], r.severity);
  EXPECT_EQ(config_from_json(json()).mode, Mode::warn);  // absent section
}

TEST(LintConfig, ParsesEveryKey) {
  const Config c = config_from_json(json::parse(R"({
    "mode": "strict", "timing": false, "findings_per_second": 0, "recent": 7,
    "max_stores_per_hour": 3, "refgo_min_response_ms": 13, "faulhaber_min_response_ms": 0,
    "code_calls_without_wait": 50, "basic_statements_without_wait": 60, "script_flash_window_ms": 1000,
    "rules": {"cia402.command_ignored": "error", "refgo.faster_than_drive": "off", "storage.store_rate": "info"}
  })"));
  EXPECT_EQ(c.mode, Mode::strict);
  EXPECT_FALSE(c.timing);
  EXPECT_EQ(c.findings_per_second, 0U);
  EXPECT_EQ(c.recent_capacity, 7U);
  EXPECT_EQ(c.max_stores_per_hour, 3U);
  EXPECT_EQ(c.refgo_min_response_ms, 13U);
  EXPECT_EQ(c.faulhaber_min_response_ms, 0U);
  EXPECT_EQ(c.code_calls_without_wait, 50U);
  EXPECT_EQ(c.basic_statements_without_wait, 60U);
  EXPECT_EQ(c.script_flash_window_ms, 1000U);
  EXPECT_EQ(c.severity[static_cast<std::size_t>(RuleId::cia402_command_ignored)], Severity::error);
  EXPECT_FALSE(c.rule_on(RuleId::refgo_faster_than_drive));
  EXPECT_EQ(c.severity[static_cast<std::size_t>(RuleId::storage_store_rate)], Severity::info);
}

TEST(LintConfig, ErrorsNameTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"bogus": 1})", "lint.bogus: unknown key"},
      {R"({"mode": "loud"})", "lint.mode:"},
      {R"({"mode": 1})", "lint.mode:"},
      {R"({"timing": "yes"})", "lint.timing:"},
      {R"({"rules": {"cia402.nope": "warn"}})", "lint.rules.cia402.nope: unknown rule"},
      {R"({"rules": {"cia402.command_ignored": "loud"}})", "lint.rules.cia402.command_ignored:"},
      {R"({"rules": {"cia402.command_ignored": 2}})", "lint.rules.cia402.command_ignored:"},
      {R"({"rules": []})", "lint.rules:"},
      {R"({"max_stores_per_hour": 0})", "lint.max_stores_per_hour: must be 1 … 1000"},
      {R"({"recent": -1})", "lint.recent:"},
      {R"({"findings_per_second": 1.5})", "lint.findings_per_second: must be an integer"},
      {R"([1])", "lint: must be an object"},
  };
  for (const auto& [text, message] : cases) {
    try {
      config_from_json(json::parse(text));
      ADD_FAILURE() << text << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()).rfind(message, 0), 0U) << text << " → " << e.what();
    }
  }
}

TEST(LintConfig, ModeNames) {
  for (auto m : {Mode::off, Mode::warn, Mode::strict}) EXPECT_EQ(mode_from_string(to_string(m)), m);
  EXPECT_EQ(mode_from_string("on"), std::nullopt);
}

TEST(LintConfig, JsonRoundTrip) {
  Config c;
  c.mode = Mode::off;
  c.max_stores_per_hour = 42;
  c.severity[static_cast<std::size_t>(RuleId::script_busy_loop)].reset();
  c.severity[static_cast<std::size_t>(RuleId::canopen_sdo_overlap)] = Severity::error;
  const json j = to_json(c);
  EXPECT_EQ(j["rules"]["script.busy_loop"], "off");
  EXPECT_EQ(j["rules"].size(), k_rule_count);
  const Config back = config_from_json(j);
  EXPECT_EQ(back.mode, Mode::off);
  EXPECT_EQ(back.max_stores_per_hour, 42U);
  EXPECT_EQ(back.severity, c.severity);
}

TEST(LintConfig, ApplyJsonChangesOnlyTheGivenKeys) {
  Config base;
  base.refgo_min_response_ms = 9;
  const Config c = apply_json(base, json::parse(R"({"rules": {"script.busy_loop": "error"}})"));
  EXPECT_EQ(c.refgo_min_response_ms, 9U);
  EXPECT_EQ(c.severity[static_cast<std::size_t>(RuleId::script_busy_loop)], Severity::error);
}

}  // namespace
}  // namespace mcemu::lint
