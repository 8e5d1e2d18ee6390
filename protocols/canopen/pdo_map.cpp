#include "protocols/canopen/pdo_map.hpp"

#include "protocols/canopen/od_access.hpp"

namespace mcemu::canopen {

std::optional<std::vector<MapEntry>> read_mapping(const od::ObjectDictionary& od, std::uint16_t map_index) {
  const auto count = stored_number(od, map_index, 0);
  if (!count) return std::nullopt;
  std::vector<MapEntry> out;
  for (std::int64_t s = 1; s <= *count && s <= 8; ++s) {
    const auto raw = stored_number(od, map_index, static_cast<std::uint8_t>(s));
    if (!raw) break;
    out.push_back(MapEntry::decode(static_cast<std::uint32_t>(*raw)));
  }
  return out;
}

std::size_t mapped_bytes(const std::vector<MapEntry>& map) {
  std::size_t n = 0;
  for (const auto& e : map) n += (e.bits + 7u) / 8u;
  return n;
}

std::vector<std::uint8_t> build_payload(const od::ObjectDictionary& od, const std::vector<MapEntry>& map) {
  std::vector<std::uint8_t> out;
  for (const auto& e : map) {
    const std::size_t n = (e.bits + 7u) / 8u;
    const std::size_t start = out.size();
    out.resize(start + n, 0);
    if (e.dummy()) continue;
    auto bytes = od.read_bytes(e.index, e.sub);
    if (!bytes) continue;
    for (std::size_t i = 0; i < n && i < bytes->size(); ++i)
      out[start + i] = std::to_integer<std::uint8_t>((*bytes)[i]);
  }
  if (out.size() > 8) out.resize(8);
  return out;
}

}  // namespace mcemu::canopen
