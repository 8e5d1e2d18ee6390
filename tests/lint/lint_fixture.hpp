// A lint engine that keeps every finding it reports, and builders for the observations the tests
// feed (drive time in ms; connection 1 unless given).
#pragma once

#include <algorithm>
#include <vector>

#include "lint/engine.hpp"

namespace mcemu::lint::test {

struct Lint {
  std::vector<Finding> found;
  Engine engine;

  explicit Lint(Config c = {}) : engine(std::move(c), [this](const Finding& f) { found.push_back(f); }) {}

  std::size_t count(RuleId id) const {
    return static_cast<std::size_t>(
        std::count_if(found.begin(), found.end(), [id](const Finding& f) { return f.rule == id; }));
  }
  // Every reported finding is of rule `id` (and there is at least one).
  bool only(RuleId id) const { return !found.empty() && count(id) == found.size(); }

  // The drive as a master would find it: statusword and mode display (core events).
  void drive_at(Ms t, std::uint16_t statusword, std::int8_t mode = 1) {
    const core::Event sw = core::StatuswordChanged{0, statusword};
    engine.observe(CoreEvent{t, sw});
    const core::Event md = core::ModeDisplayChanged{mode};
    engine.observe(CoreEvent{t, md});
  }
};

inline OdWrite write(Ms t, std::uint16_t index, std::int64_t value, std::uint16_t sw_after, std::int8_t mode_after = 1,
                     od::Origin origin = od::Origin::sdo, Conn conn = 1) {
  OdWrite w;
  w.time = t;
  w.conn = conn;
  w.origin = origin;
  w.index = index;
  w.value = value;
  w.statusword_after = sw_after;
  w.mode_after = mode_after;
  return w;
}

inline OdWrite helper_write(OdWrite w) {
  w.helper = true;
  return w;
}

inline OdWrite refused(OdWrite w, od::AbortCode c = od::AbortCode::invalid_value) {
  w.result = c;
  return w;
}

}  // namespace mcemu::lint::test
