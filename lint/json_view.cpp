#include "lint/json_view.hpp"

#include <string>

#include "lint/reporter.hpp"

namespace mcemu::lint {

nlohmann::json to_json(const Finding& f) {
  const RuleInfo& r = info(f.rule);
  return nlohmann::json{{"seq", f.seq},           {"rule", r.name},     {"severity", to_string(f.severity)},
                        {"time_ms", f.time_ms},   {"conn", f.conn},     {"origin", f.origin},
                        {"detail", f.detail},     {"advice", r.advice}, {"reference", r.reference},
                        {"text", finding_text(f)}};
}

nlohmann::json lint_json(const Engine& engine) {
  const Config& c = engine.config();
  nlohmann::json rules = nlohmann::json::array();
  std::uint64_t suppressed = 0;
  for (const auto& r : rule_table()) {
    const RuleCount& n = engine.counts(r.id);
    suppressed += n.suppressed;
    const auto& sev = c.severity[static_cast<std::size_t>(r.id)];
    const bool on = sev.has_value() && (c.timing || !r.timing);
    nlohmann::json row{{"id", r.name},
                       {"family", r.family},
                       {"severity", on ? std::string(to_string(*sev)) : std::string("off")},
                       {"default_severity", to_string(r.severity)},
                       {"timing", r.timing},
                       {"summary", r.summary},
                       {"advice", r.advice},
                       {"reference", r.reference},
                       {"count", n.occurrences},
                       {"reported", n.reported},
                       {"suppressed", n.suppressed}};
    row["last_time_ms"] = n.occurrences ? nlohmann::json(n.last_time_ms) : nlohmann::json(nullptr);
    rules.push_back(std::move(row));
  }
  nlohmann::json recent = nlohmann::json::array();
  for (const auto& f : engine.recent()) recent.push_back(to_json(f));
  return nlohmann::json{{"mode", to_string(c.mode)},
                        {"timing", c.timing},
                        {"totals",
                         {{"info", engine.total(Severity::info)},
                          {"warn", engine.total(Severity::warn)},
                          {"error", engine.total(Severity::error)},
                          {"suppressed", suppressed},
                          {"failing", engine.failing()}}},
                        {"rules", std::move(rules)},
                        {"recent", std::move(recent)}};
}

}  // namespace mcemu::lint
