// The CiA 402 rules (docs/lint.md §4.1): what a master's controlword, mode and target writes do to
// a real drive. Judged on each OdWrite against the DriveView as it was before the write; no state
// of their own.
#pragma once

#include "lint/drive_view.hpp"
#include "lint/reporter.hpp"

namespace mcemu::lint {

// `before` = the view before the write; `at` = the write's time, connection and origin.
void cia402_rules(const OdWrite& w, const DriveView& before, const At& at, Reporter& rep);

}  // namespace mcemu::lint
