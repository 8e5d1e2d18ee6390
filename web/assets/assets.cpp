#include "web/assets/assets.hpp"

#include <algorithm>

namespace mcemu::web::assets {

const Asset* find(std::string_view path) {
  const auto table = all();
  const auto it =
      std::lower_bound(table.begin(), table.end(), path, [](const Asset& a, std::string_view p) { return a.path < p; });
  if (it == table.end() || it->path != path) return nullptr;
  return &*it;
}

}  // namespace mcemu::web::assets
