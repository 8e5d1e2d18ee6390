// The storage rules (docs/lint.md §4.2) and the script rules (§4.5): stores to non-volatile memory
// (1010h, 1011h, 3010h.01 writes and FlashWrite observations) — how often, while moving, in a
// script loop — and script loops that never wait. State: the times of the last stores (a ring of
// max_stores_per_hour entries), the last script store, one "armed" flag per script kind.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include "lint/drive_view.hpp"
#include "lint/reporter.hpp"

namespace mcemu::lint {

// The store an accepted write performs, if any (persistence.md §3, §4: the "save"/"load" signatures).
std::optional<FlashKind> flash_kind_of(const OdWrite& w);

class StorageRules {
 public:
  void configure(const Config& c);
  void on_flash(FlashKind kind, od::Origin origin, const DriveView& v, const At& at, Reporter& rep);
  void on_script_loop(const ScriptLoop& s, const At& at, Reporter& rep);
  void power_on();

 private:
  const Config* config_ = nullptr;
  std::vector<Ms> stores_;  // mono times of the last stores, circular
  std::size_t next_ = 0;
  std::optional<Ms> last_script_store_;
  std::array<bool, 2> armed_{true, true};  // per ScriptKind
};

}  // namespace mcemu::lint
