// PDO mapping as read from the OD (slcan-canopen.md §9.1, §9.7): entries `IIII SS LL` of
// 16xxh/1Axxh, and packing/unpacking of mapped values little-endian in entry order. Pure.
#pragma once

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
// Current values of the mapped objects, packed (dummies and unreadable entries as zero bytes).
std::vector<std::uint8_t> build_payload(const od::ObjectDictionary& od, const std::vector<MapEntry>& map);

}  // namespace mcemu::canopen
