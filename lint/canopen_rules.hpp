// The CANopen rules (docs/lint.md §4.3): NMT state versus SDO/PDO traffic, one SDO transfer at a
// time, PDO mapping without invalidating, motion by RPDO without node guarding, traffic before
// the boot-up. State: the NMT state, whether an SDO request waits for its answer, a block download
// in progress, a guarding RTR seen since the boot-up, the once-per-OPERATIONAL guarding finding.
#pragma once

#include <optional>

#include "lint/reporter.hpp"

namespace mcemu::lint {

std::string_view to_string(Nmt n);  // "PRE-OPERATIONAL"

class CanopenRules {
 public:
  void on_nmt(const NmtChange& n);
  void on_request(const CanRequest& r, const At& at, Reporter& rep);
  void on_answer(const SdoAnswer& a);
  void on_mapping(const PdoMappingWrite& m, const At& at, Reporter& rep);

 private:
  std::optional<Nmt> nmt_;  // unknown until the first NmtChange
  bool sdo_waiting_ = false;
  bool block_download_ = false;
  bool guarding_seen_ = false;
  bool guarding_reported_ = false;
};

}  // namespace mcemu::lint
