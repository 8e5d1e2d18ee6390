#include "protocols/canopen/pdo_map.hpp"

#include <algorithm>
#include <string>

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

ResolvedMap resolve_mapping(const od::ObjectDictionary& od, const std::vector<MapEntry>& map) {
  ResolvedMap r;
  for (const auto& e : map) {
    if (r.count == r.entries.size()) break;
    ResolvedMap::Entry& out = r.entries[r.count++];
    out.bytes = static_cast<std::uint8_t>((e.bits + 7u) / 8u);
    if (e.dummy()) continue;
    const auto h = od.find(e.index, e.sub);
    if (h && od.info(*h).access != od::Access::wo) out.handle = h;
  }
  return r;
}

PdoData build_payload(const od::ObjectDictionary& od, const ResolvedMap& map) {
  PdoData out;
  std::size_t at = 0;
  for (std::size_t k = 0; k < map.count && at < out.bytes.size(); ++k) {
    const ResolvedMap::Entry& e = map.entries[k];
    const std::size_t n = std::min<std::size_t>(e.bytes, out.bytes.size() - at);
    if (e.handle) {
      if (const auto v = od.read(*e.handle)) {
        if (const auto* number = std::get_if<std::int64_t>(&*v)) {
          const auto raw = static_cast<std::uint64_t>(*number);
          const std::size_t width = std::min(n, od::size_of(od.info(*e.handle).type));
          for (std::size_t i = 0; i < width; ++i) out.bytes[at + i] = static_cast<std::uint8_t>(raw >> (8 * i));
        } else {
          const auto& text = std::get<std::string>(*v);
          for (std::size_t i = 0; i < n && i < text.size(); ++i) out.bytes[at + i] = static_cast<std::uint8_t>(text[i]);
        }
      }
    }
    at += n;
  }
  out.size = static_cast<std::uint8_t>(at);
  return out;
}

}  // namespace mcemu::canopen
