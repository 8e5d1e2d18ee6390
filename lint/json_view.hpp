// JSON views of the lint for the HTTP API (web.md-style bodies; the route is wired elsewhere):
// GET /api/v1/lint → lint_json(engine): the mode, totals, every rule with its explanation,
// reference and counts, and the recent findings with all their fields.
#pragma once

#include <nlohmann/json.hpp>

#include "lint/engine.hpp"

namespace mcemu::lint {

nlohmann::json to_json(const Finding& f);
// {"mode", "timing", "totals": {"info", "warn", "error", "suppressed", "failing"},
//  "rules": [{"id", "family", "severity" ("off" when off), "default_severity", "timing", "summary",
//             "advice", "reference", "count", "reported", "suppressed", "last_time_ms"}],
//  "recent": [finding…] (oldest first)}
nlohmann::json lint_json(const Engine& engine);

}  // namespace mcemu::lint
