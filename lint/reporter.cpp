#include "lint/reporter.hpp"

namespace mcemu::lint {

std::string finding_text(const Finding& f) {
  const RuleInfo& r = info(f.rule);
  std::string s;
  s.reserve(r.name.size() + f.detail.size() + r.advice.size() + r.reference.size() + 16);
  s.append(r.name).append(" ").append(to_string(f.severity)).append(": ").append(f.detail);
  s.append(" — ").append(r.advice).append(" [").append(r.reference).append("]");
  return s;
}

std::array<bool, k_rule_count> Reporter::timing_flags() {
  std::array<bool, k_rule_count> a{};
  for (const auto& r : rule_table()) a[static_cast<std::size_t>(r.id)] = r.timing;
  return a;
}

void Reporter::resize() {
  const std::size_t cap = config_->recent_capacity == 0 ? 1 : config_->recent_capacity;
  if (cap == capacity_) return;
  std::vector<Finding> kept = recent();
  if (kept.size() > cap) kept.erase(kept.begin(), kept.end() - static_cast<std::ptrdiff_t>(cap));
  capacity_ = cap;
  ring_ = std::move(kept);
  ring_.reserve(cap);
  head_ = 0;
}

bool Reporter::count(RuleId id, const At& at) {
  const auto i = static_cast<std::size_t>(id);
  const auto sev = static_cast<std::size_t>(*config_->severity[i]);
  RuleCount& c = counts_[i];
  ++c.occurrences;
  c.last_time_ms = at.time;
  ++totals_[sev];
  const std::uint32_t limit = config_->findings_per_second;
  Window& w = windows_[i];
  const Ms second = at.mono / 1000;
  if (second != w.second) w = Window{second, 0};
  if (limit != 0 && w.reported >= limit) {
    ++c.suppressed;
    return false;
  }
  ++w.reported;
  ++c.reported;
  return true;
}

void Reporter::record(RuleId id, const At& at, std::string detail) {
  Finding f;
  f.seq = ++seq_;
  f.rule = id;
  f.severity = *config_->severity[static_cast<std::size_t>(id)];
  f.time_ms = at.time;
  f.conn = at.conn;
  f.origin = at.origin;
  f.detail = std::move(detail);
  if (sink_) sink_(f);
  if (ring_.size() < capacity_) {
    ring_.push_back(std::move(f));
  } else {
    ring_[head_] = std::move(f);
    head_ = (head_ + 1) % ring_.size();
  }
}

std::uint64_t Reporter::failing() const {
  const std::uint64_t errors = totals_[static_cast<std::size_t>(Severity::error)];
  if (config_->mode != Mode::strict) return errors;
  return errors + totals_[static_cast<std::size_t>(Severity::warn)];
}

std::vector<Finding> Reporter::recent() const {
  std::vector<Finding> v;
  v.reserve(ring_.size());
  for (std::size_t i = 0; i < ring_.size(); ++i) v.push_back(ring_[(head_ + i) % ring_.size()]);
  return v;
}

void Reporter::reset() {
  counts_ = {};
  windows_ = {};
  totals_ = {};
  ring_.clear();
  head_ = 0;
}

}  // namespace mcemu::lint
