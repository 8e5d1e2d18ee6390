// The master lint (docs/lint.md): it watches what a master, a host or a script does to one drive
// and reports what a real drive would punish — ignored controlwords, lost set-points, flash wear,
// SDO to a stopped node, requests that race replies. One engine per drive bundle.
//
// Contract: pure and single-threaded (event-loop thread). It is fed observations (observations.hpp)
// in the order things happened; it never reads the drive, never reads a clock and has no step: an
// idle drive costs nothing, and every rule gets its time from the observations. Each observation
// costs O(1) (a few branches; a finding formats one string). With mode off every observe() returns
// at once and nothing is tracked. Findings go to the sink (the bundle puts them on the trace channel
// `lint`) and are counted per rule, rate-limited per rule and second of drive time, and kept in a
// ring of the last `recent` findings.
#pragma once

#include <cstdint>
#include <vector>

#include "lint/canopen_rules.hpp"
#include "lint/config.hpp"
#include "lint/drive_view.hpp"
#include "lint/link_rules.hpp"
#include "lint/observations.hpp"
#include "lint/reporter.hpp"
#include "lint/storage_rules.hpp"

namespace mcemu::lint {

class Engine {
 public:
  using Sink = Reporter::Sink;

  explicit Engine(Config config = {}, Sink sink = {});
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  void set_sink(Sink sink) { reporter_.set_sink(std::move(sink)); }
  // A new configuration (runtime change): counts and findings are kept; the store-rate history
  // restarts.
  void configure(Config config);
  const Config& config() const { return config_; }
  bool active() const { return config_.mode != Mode::off; }

  void observe(const OdWrite& w);
  void observe(const CoreEvent& e);
  void observe(const PowerOn& p);
  void observe(const NmtChange& n);
  void observe(const CanRequest& r);
  void observe(const SdoAnswer& a);
  void observe(const PdoMappingWrite& m);
  void observe(const ProtocolRequest& r);
  void observe(const ProtocolReply& r);
  void observe(const ConnectionClosed& c);
  void observe(const ScriptLoop& s);
  void observe(const FlashWrite& f);

  const RuleCount& counts(RuleId id) const { return reporter_.counts(id); }
  // Occurrences (reported and suppressed) at each severity since the last reset.
  std::uint64_t total(Severity s) const { return reporter_.total(s); }
  // Occurrences that fail a strict test: error level, plus warn level in mode strict.
  std::uint64_t failing() const { return reporter_.failing(); }
  std::vector<Finding> recent() const { return reporter_.recent(); }  // oldest first
  // DELETE /api/v1/lint: counts and recent findings cleared; what the lint knows of the drive stays.
  void reset() { reporter_.reset(); }

  const DriveView& view() const { return view_; }

 private:
  // Drive time continued across power cycles (drive time restarts at 0 there).
  Ms mono(Ms drive_time);

  Config config_;
  Reporter reporter_;
  DriveView view_;
  StorageRules storage_;
  CanopenRules canopen_;
  LinkRules links_;
  Ms last_drive_ = 0;
  Ms offset_ = 0;
};

}  // namespace mcemu::lint
