// Basic vocabulary of the object dictionary: CiA 301 data types, access, entry classes, origins
// and the value type. Pure; no allocation beyond std::string values.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

namespace mcemu::od {

// CiA 301 basic types used by the MovingCap dictionaries (object-dictionary.md §2.2).
enum class DataType : std::uint16_t {
  boolean = 0x0001,
  integer8 = 0x0002,
  integer16 = 0x0003,
  integer32 = 0x0004,
  unsigned8 = 0x0005,
  unsigned16 = 0x0006,
  unsigned32 = 0x0007,
  visible_string = 0x0009,
};

// const_ because `const` is a keyword.
enum class Access : std::uint8_t { ro, wo, rw, const_ };

enum class PdoFlag : std::uint8_t { no, rpdo, tpdo, optional };

// What start-up, Store and Restore do with an entry (object-dictionary.md §2.6).
enum class EntryClass : std::uint8_t { const_, live, param, comm, proc, cmd };

// Who writes (object-dictionary.md §3). Only `internal` may write ro/const entries.
enum class Origin : std::uint8_t { sdo, refgo, script, web, internal };

// Either an integer (held as int64 whatever the entry's type) or the characters of a string.
using Value = std::variant<std::int64_t, std::string>;

struct Range {
  std::int64_t min;
  std::int64_t max;
};

constexpr bool is_string(DataType t) { return t == DataType::visible_string; }

// Size in bytes of a numeric type; 0 for strings.
constexpr std::size_t size_of(DataType t) {
  switch (t) {
    case DataType::boolean:
    case DataType::integer8:
    case DataType::unsigned8: return 1;
    case DataType::integer16:
    case DataType::unsigned16: return 2;
    case DataType::integer32:
    case DataType::unsigned32: return 4;
    case DataType::visible_string: return 0;
  }
  return 0;
}

constexpr bool is_signed(DataType t) {
  return t == DataType::integer8 || t == DataType::integer16 || t == DataType::integer32;
}

constexpr Range type_range(DataType t) {
  switch (t) {
    case DataType::boolean: return {0, 1};
    case DataType::integer8: return {-128, 127};
    case DataType::integer16: return {-32768, 32767};
    case DataType::integer32: return {-2147483648LL, 2147483647LL};
    case DataType::unsigned8: return {0, 255};
    case DataType::unsigned16: return {0, 65535};
    case DataType::unsigned32: return {0, 4294967295LL};
    case DataType::visible_string: return {0, 0};
  }
  return {0, 0};
}

std::string_view to_string(DataType t);    // CiA name, e.g. "UNSIGNED32"
std::string_view to_string(Access a);      // "ro", "wo", "rw", "const"
std::string_view to_string(PdoFlag p);     // "no", "RPDO", "TPDO", "optional"
std::string_view to_string(EntryClass c);  // "const", "live", "param", "comm", "proc", "cmd"
std::string_view to_string(Origin o);      // "sdo", "refgo", "script", "web", "internal"
std::optional<DataType> data_type_from_string(std::string_view cia_name);

}  // namespace mcemu::od
