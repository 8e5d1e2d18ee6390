// The lint's configuration (docs/lint.md §3): the global mode (`--lint off|warn|strict`), a
// severity or "off" per rule, and the limits some rules compare with. Parsed from the "lint"
// section of --config; a bad key or value throws std::invalid_argument naming the key.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string_view>

#include "lint/rules.hpp"

namespace mcemu::lint {

// off: observations are dropped at once (nothing tracked, nothing reported);
// warn: findings are reported and counted; strict: as warn, and warn-level findings count as
// failures for the test kit (Engine::failing()).
enum class Mode : std::uint8_t { off, warn, strict };

std::string_view to_string(Mode m);
std::optional<Mode> mode_from_string(std::string_view s);

struct Config {
  Mode mode = Mode::warn;
  // nullopt = the rule is off; else its severity. Starts as the table's defaults.
  std::array<std::optional<Severity>, k_rule_count> severity = default_severities();
  // false: the rules that compare drive-time intervals (RuleInfo::timing) are off — for a manual
  // clock, where drive time stands still between requests.
  bool timing = true;
  // Rate limit: at most this many findings of one rule per second of drive time are reported;
  // the rest are counted as suppressed. 0 = no limit.
  std::uint32_t findings_per_second = 5;
  std::uint32_t recent_capacity = 100;                 // last findings kept for the API
  std::uint32_t max_stores_per_hour = 10;              // storage.store_rate (1…1000)
  std::uint32_t refgo_min_response_ms = 4;             // refgo.faster_than_drive (0 = off)
  std::uint32_t faulhaber_min_response_ms = 2;         // faulhaber.faster_than_drive (0 = off)
  std::uint32_t code_calls_without_wait = 1000;        // script.busy_loop, MovingCap CODE
  std::uint32_t basic_statements_without_wait = 2000;  // script.busy_loop, MC BASIC
  std::uint32_t script_flash_window_ms = 60000;        // script.flash_write_in_loop

  static std::array<std::optional<Severity>, k_rule_count> default_severities();
  bool rule_on(RuleId id) const { return severity[static_cast<std::size_t>(id)].has_value(); }
};

// The "lint" section: {"mode": "off|warn|strict", "rules": {"ID": "off|info|warn|error"},
// "timing": bool, "findings_per_second": n, "recent": n, "max_stores_per_hour": n,
// "refgo_min_response_ms": n, "faulhaber_min_response_ms": n, "code_calls_without_wait": n,
// "basic_statements_without_wait": n, "script_flash_window_ms": n}. Every key is optional; an
// unknown key, an unknown rule id, a wrong type or a value out of range throws
// std::invalid_argument("lint.rules.cia402.command_ignored: …").
Config config_from_json(const nlohmann::json& section);
// Applies the section over `base` (the same rules); for runtime changes.
Config apply_json(Config base, const nlohmann::json& section);
nlohmann::json to_json(const Config& c);

}  // namespace mcemu::lint
