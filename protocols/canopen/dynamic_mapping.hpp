// The CiA 301 dynamic PDO mapping mode of slcan-canopen.md §9.7 (config
// `canopen.dynamic_pdo_mapping`, off by default: real MovingCaps have fixed, const mappings).
//
// make_mapping_dynamic() rewrites a preset's entry list before the dictionary is built: every
// mapping object 1600h–1603h / 1A00h–1A03h gets sub-indices 00h…08h, all rw, class comm (stored by
// 1010h, reloaded at reset communication). DynamicMapping then registers the write rules on the
// dictionary (mapping writes only while the PDO is invalid, entries only while sub 00h = 0,
// mappable objects and lengths, 64-bit limit, no enabling with an empty mapping). Pure.
#pragma once

#include <vector>

#include "drive/od/dictionary.hpp"

namespace mcemu::canopen {

void make_mapping_dynamic(std::vector<od::EntryInfo>& entries);

// Registers the §9.7 write hooks on the mapping objects and the PDO COB-IDs; removes them in its
// destructor. Only for a dictionary built from make_mapping_dynamic() entries.
class DynamicMapping {
 public:
  explicit DynamicMapping(od::ObjectDictionary& od);
  ~DynamicMapping();
  DynamicMapping(const DynamicMapping&) = delete;
  DynamicMapping& operator=(const DynamicMapping&) = delete;

 private:
  od::ObjectDictionary& od_;
};

}  // namespace mcemu::canopen
