// Reading the fields of JSON requests the bundle decodes itself (fault kinds, settings) the way
// the JSON API does everywhere (web.md §8): indices and codes as hex strings or numbers, bounded
// unsigned integers, and JSON text that never throws on raw bytes.
// PURE: plain values; nothing here throws on any input.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace mcemu::device {

// JSON text of a value; invalid UTF-8 (raw RefGo bytes 0x80–0xFF) becomes U+FFFD instead of throwing.
std::string dump_json(const nlohmann::json& j);
// "6041", "6041h", "0x6041" → 0x6041 if ≤ max; sub-indices likewise ("0", "01h").
std::optional<std::uint32_t> parse_hex_token(std::string_view text, std::uint32_t max);
// A JSON index/sub-index/code: a string is hex as above, a number is its plain value (web.md §8).
std::optional<std::uint32_t> json_hex_or_number(const nlohmann::json& v, std::uint32_t max);
// A JSON value as a non-negative integer in [min, max], or nullopt.
std::optional<std::uint64_t> json_uint(const nlohmann::json& v, std::uint64_t min, std::uint64_t max);

}  // namespace mcemu::device
