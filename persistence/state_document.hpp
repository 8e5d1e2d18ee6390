// The stored image and its file format (persistence.md §2, §9, §11). Pure: JSON in, JSON out, no
// files and no clocks (the caller passes the time stamp).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drive/od/dictionary.hpp"

namespace mcemu::persistence {

inline constexpr std::string_view k_format = "mcemu-drive-state";
inline constexpr int k_format_version = 1;
inline constexpr std::string_view k_plant_format = "mcemu-plant-state";

// Which Store/Restore group an entry belongs to (persistence.md §2).
enum class Group : std::uint8_t { none, parameters, motor, network, nvm };
Group group_of(const od::EntryInfo& info);

// The payload of a state file.
struct Image {
  std::vector<od::StoredValue> objects;  // every persistent entry
  std::int64_t home_offset_inc = 0;
  bool autostart = false;
  nlohmann::json script;  // null = placeholder script; otherwise the object of §9 (kept opaque here)
};

// Snapshot of every persistent entry of the dictionary (stored values, no read hooks).
Image snapshot(const od::ObjectDictionary& od);

// "IIII.SS" with upper-case hex.
std::string object_key(std::uint16_t index, std::uint8_t sub);
std::optional<std::pair<std::uint16_t, std::uint8_t>> parse_object_key(std::string_view key);

std::uint32_t crc32(std::string_view bytes);  // IEEE 802.3 / zlib
std::string hex32(std::uint32_t v);           // "0x8a41c0de"

// The complete file text (keys sorted, 2-space indent, LF line ends, trailing LF): what
// nlohmann-json's dump(2) of the document would be, written without building it. payload_crc32 is
// the CRC of the payload's compact form (dump()); a string that is not UTF-8 throws as dump() does.
std::string serialize(const Image& image, std::string_view model, std::string_view mcemu_version,
                      std::string_view written_utc);

struct ParsedFile {
  Image image;
  std::vector<std::string> bad_keys;  // unknown object or value out of range / wrong type (§11)
};
inline constexpr std::size_t k_max_state_file_bytes = 16 * 1024 * 1024;
inline constexpr std::size_t k_max_state_objects = 65536;
struct ParseFailure {
  std::string reason;  // for the "is corrupt (<reason>)" warning
};
// Validates format, version, model and payload_crc32, then checks each object against `od`'s entry
// rules (type and §5 limits, without changing `od`).
std::variant<ParsedFile, ParseFailure> parse(std::string_view text, std::string_view running_model,
                                             const od::ObjectDictionary& od);

// drive-N.plant.json (persistence.md §8).
std::string serialize_plant(std::string_view model, std::int64_t raw_position_inc);
std::optional<std::int64_t> parse_plant(std::string_view text, std::string_view running_model);

}  // namespace mcemu::persistence
