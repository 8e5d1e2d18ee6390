// The reporting half of the lint engine: severities from the config, the rate limit per rule,
// counts, the ring of recent findings and the sink. Rule families call fire(); the detail text is
// built only for a finding that passes the rate limit.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "lint/config.hpp"
#include "lint/observations.hpp"
#include "lint/rules.hpp"

namespace mcemu::lint {

struct Finding {
  std::uint64_t seq = 0;  // 1, 2, … in order of reporting (reset() keeps counting)
  RuleId rule = RuleId::cia402_command_ignored;
  Severity severity = Severity::warn;  // as configured when it fired
  Ms time_ms = 0;                      // drive time of the observation
  Conn conn = 0;
  std::string_view origin;  // "sdo", "refgo", "script", "web", "canopen", "faulhaber", "basic", …
  std::string detail;       // what happened, with the values
};

// "cia402.command_ignored warn: <detail> — <advice> [<reference>]" (the trace line).
std::string finding_text(const Finding& f);

struct RuleCount {
  std::uint64_t occurrences = 0;  // reported + suppressed
  std::uint64_t reported = 0;
  std::uint64_t suppressed = 0;  // over the rate limit
  Ms last_time_ms = 0;           // drive time of the last occurrence
};

// Where and when an observation happened: drive time, the lint's monotonic time (drive time
// continued across power cycles), connection and origin.
struct At {
  Ms time = 0;
  Ms mono = 0;
  Conn conn = 0;
  std::string_view origin;
};

class Reporter {
 public:
  using Sink = std::function<void(const Finding&)>;

  explicit Reporter(const Config& config) : config_(&config) { resize(); }

  void set_sink(Sink sink) { sink_ = std::move(sink); }
  void resize();  // after the config changed: the recent ring's capacity

  // True when the rule is switched on (severity set, timing allowed).
  bool on(RuleId id) const {
    const auto i = static_cast<std::size_t>(id);
    return config_->severity[i].has_value() && (config_->timing || !timing_[i]);
  }

  // One occurrence of a rule. `detail` (a callable returning std::string) runs only when the
  // finding is reported.
  template <typename Detail>
  void fire(RuleId id, const At& at, Detail&& detail) {
    if (!on(id)) return;
    if (count(id, at)) record(id, at, std::forward<Detail>(detail)());
  }

  const RuleCount& counts(RuleId id) const { return counts_[static_cast<std::size_t>(id)]; }
  std::uint64_t total(Severity s) const { return totals_[static_cast<std::size_t>(s)]; }
  std::uint64_t failing() const;
  std::vector<Finding> recent() const;  // oldest first
  void reset();

 private:
  bool count(RuleId id, const At& at);  // counts the occurrence; true = within the rate limit
  void record(RuleId id, const At& at, std::string detail);

  struct Window {
    Ms second = 0;
    std::uint32_t reported = 0;
  };

  const Config* config_;
  Sink sink_;
  std::array<bool, k_rule_count> timing_ = timing_flags();
  std::array<RuleCount, k_rule_count> counts_{};
  std::array<Window, k_rule_count> windows_{};
  std::array<std::uint64_t, 3> totals_{};  // occurrences by severity
  std::vector<Finding> ring_;
  std::size_t capacity_ = 0;
  std::size_t head_ = 0;  // next slot to overwrite once the ring is full
  std::uint64_t seq_ = 0;

  static std::array<bool, k_rule_count> timing_flags();
};

}  // namespace mcemu::lint
