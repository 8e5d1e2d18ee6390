// PDO mapping as read from the OD (slcan-canopen.md §9.1, §9.7): entries `IIII SS LL` of
// 16xxh/1Axxh, and packing of mapped values little-endian in entry order. Pure.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "drive/od/dictionary.hpp"

namespace mcemu::canopen {

struct MapEntry {
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::uint8_t bits = 0;
  bool dummy() const { return index >= 0x0002 && index <= 0x0007; }
  static MapEntry decode(std::uint32_t raw) {
    return {static_cast<std::uint16_t>(raw >> 16), static_cast<std::uint8_t>((raw >> 8) & 0xFF),
            static_cast<std::uint8_t>(raw & 0xFF)};
  }
};

// The entries 01h…(00h) of a mapping object; nullopt if the object does not exist.
std::optional<std::vector<MapEntry>> read_mapping(const od::ObjectDictionary& od, std::uint16_t map_index);
// Total mapped length in bytes (bits rounded up per entry; only whole-byte entries are allowed).
std::size_t mapped_bytes(const std::vector<MapEntry>& map);

// A mapping resolved against its dictionary once (a handle per readable entry), so that the payload
// a TPDO compares every step is built without a lookup or an allocation.
struct ResolvedMap {
  struct Entry {
    std::optional<od::Handle> handle;  // none: a dummy, an absent or a write-only entry (zero bytes)
    std::uint8_t bytes = 0;            // bits rounded up
  };
  std::array<Entry, 8> entries{};
  std::uint8_t count = 0;
};
ResolvedMap resolve_mapping(const od::ObjectDictionary& od, const std::vector<MapEntry>& map);

// At most 8 bytes of mapped values; the bytes past `size` stay zero, so equal payloads compare equal.
struct PdoData {
  std::array<std::uint8_t, 8> bytes{};
  std::uint8_t size = 0;
  bool operator==(const PdoData&) const = default;
};
// Current values of the mapped objects (read hooks run), packed; dummies and entries that cannot
// be read give zero bytes; cut at 8 bytes.
PdoData build_payload(const od::ObjectDictionary& od, const ResolvedMap& map);

}  // namespace mcemu::canopen
