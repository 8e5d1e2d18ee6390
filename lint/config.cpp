#include "lint/config.hpp"

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace mcemu::lint {

namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) {
  throw std::invalid_argument("lint." + key + ": " + why);
}

std::uint32_t bounded(const nlohmann::json& v, const std::string& key, std::uint32_t min, std::uint32_t max) {
  if (!v.is_number_integer()) bad(key, "must be an integer");
  const auto n = v.get<std::int64_t>();
  if (n < min || n > max) bad(key, "must be " + std::to_string(min) + " … " + std::to_string(max));
  return static_cast<std::uint32_t>(n);
}

struct Limit {
  std::string_view key;
  std::uint32_t Config::*field;
  std::uint32_t min;
  std::uint32_t max;
};

// The numeric keys, one row each (dispatch by table).
constexpr Limit k_limits[] = {
    {"findings_per_second", &Config::findings_per_second, 0, 1000000},
    {"recent", &Config::recent_capacity, 1, 10000},
    {"max_stores_per_hour", &Config::max_stores_per_hour, 1, 1000},
    {"refgo_min_response_ms", &Config::refgo_min_response_ms, 0, 10000},
    {"faulhaber_min_response_ms", &Config::faulhaber_min_response_ms, 0, 10000},
    {"code_calls_without_wait", &Config::code_calls_without_wait, 1, 100000000},
    {"basic_statements_without_wait", &Config::basic_statements_without_wait, 1, 100000000},
    {"script_flash_window_ms", &Config::script_flash_window_ms, 1, 86400000},
};

}  // namespace

std::string_view to_string(Mode m) {
  switch (m) {
    case Mode::off: return "off";
    case Mode::warn: return "warn";
    case Mode::strict: break;
  }
  return "strict";
}

std::optional<Mode> mode_from_string(std::string_view s) {
  if (s == "off") return Mode::off;
  if (s == "warn") return Mode::warn;
  if (s == "strict") return Mode::strict;
  return std::nullopt;
}

std::array<std::optional<Severity>, k_rule_count> Config::default_severities() {
  std::array<std::optional<Severity>, k_rule_count> a;
  for (const auto& r : rule_table()) a[static_cast<std::size_t>(r.id)] = r.severity;
  return a;
}

Config config_from_json(const nlohmann::json& section) { return apply_json(Config{}, section); }

Config apply_json(Config c, const nlohmann::json& section) {
  if (section.is_null()) return c;
  if (!section.is_object()) throw std::invalid_argument("lint: must be an object");
  for (const auto& [key, v] : section.items()) {
    if (key == "mode") {
      const auto m = v.is_string() ? mode_from_string(v.get<std::string>()) : std::nullopt;
      if (!m) bad(key, "must be \"off\", \"warn\" or \"strict\"");
      c.mode = *m;
    } else if (key == "timing") {
      if (!v.is_boolean()) bad(key, "must be true or false");
      c.timing = v.get<bool>();
    } else if (key == "rules") {
      if (!v.is_object()) bad(key, "must be an object of rule ids");
      for (const auto& [name, level] : v.items()) {
        const std::string rule_key = "rules." + name;
        const auto id = rule_from_name(name);
        if (!id) bad(rule_key, "unknown rule (docs/lint.md lists the rules)");
        const std::string text = level.is_string() ? level.get<std::string>() : std::string();
        auto& slot = c.severity[static_cast<std::size_t>(*id)];
        if (text == "off") {
          slot.reset();
        } else if (const auto s = severity_from_string(text)) {
          slot = *s;
        } else {
          bad(rule_key, "must be \"off\", \"info\", \"warn\" or \"error\"");
        }
      }
    } else {
      bool known = false;
      for (const auto& l : k_limits) {
        if (l.key == key) {
          c.*(l.field) = bounded(v, key, l.min, l.max);
          known = true;
        }
      }
      if (!known) bad(key, "unknown key");
    }
  }
  return c;
}

nlohmann::json to_json(const Config& c) {
  nlohmann::json j;
  j["mode"] = to_string(c.mode);
  j["timing"] = c.timing;
  for (const auto& l : k_limits) j[std::string(l.key)] = c.*(l.field);
  nlohmann::json rules = nlohmann::json::object();
  for (const auto& r : rule_table()) {
    const auto& s = c.severity[static_cast<std::size_t>(r.id)];
    rules[std::string(r.name)] = s ? std::string(to_string(*s)) : std::string("off");
  }
  j["rules"] = std::move(rules);
  return j;
}

}  // namespace mcemu::lint
