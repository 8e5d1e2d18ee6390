// Small helpers for reading communication objects that may be absent (test dictionaries, models
// without an object). Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "drive/od/dictionary.hpp"

namespace mcemu::canopen {

// The stored number of (index, sub), or nullopt when the entry does not exist or is a string.
inline std::optional<std::int64_t> stored_number(const od::ObjectDictionary& od, std::uint16_t index,
                                                 std::uint8_t sub) {
  const auto h = od.find(index, sub);
  if (!h || od::is_string(od.info(*h).type)) return std::nullopt;
  return od.number(*h);
}

inline std::int64_t stored_number_or(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub,
                                     std::int64_t fallback) {
  return stored_number(od, index, sub).value_or(fallback);
}

constexpr std::uint32_t k_cob_invalid = 0x80000000u;  // bit 31
constexpr std::uint32_t k_cob_no_rtr = 0x40000000u;   // bit 30 (TPDO)

}  // namespace mcemu::canopen
