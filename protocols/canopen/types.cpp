#include "protocols/canopen/types.hpp"

#include <algorithm>

namespace mcemu::canopen {

std::vector<can::Frame> Outbox::flatten() {
  if (empty()) return {};  // most steps of a node send nothing
  std::vector<can::Frame> out;
  out.reserve(sdo.size() + error_control.size() + emcy.size() + tpdo.size() + heartbeat.size());
  out.insert(out.end(), sdo.begin(), sdo.end());
  out.insert(out.end(), error_control.begin(), error_control.end());
  out.insert(out.end(), emcy.begin(), emcy.end());
  std::stable_sort(tpdo.begin(), tpdo.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& t : tpdo) out.push_back(t.second);
  out.insert(out.end(), heartbeat.begin(), heartbeat.end());
  sdo.clear();  // clear(), not a new Outbox: the next call reuses the capacity
  error_control.clear();
  emcy.clear();
  tpdo.clear();
  heartbeat.clear();
  return out;
}

}  // namespace mcemu::canopen
