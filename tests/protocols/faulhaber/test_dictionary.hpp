// A small FAULHABER-like dictionary for the protocol tests (the real one is built elsewhere):
// the entries the examples of faulhaber.md §5/§6 touch, with the §6 rule of 0x2400.05 as a
// validator, plus helpers to turn hex text into bytes and to build a request.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "protocols/faulhaber/describe.hpp"
#include "protocols/faulhaber/frame.hpp"

namespace mcemu::faulhaber::test {

inline od::EntryInfo entry(std::uint16_t index, std::uint8_t sub, od::DataType type, od::Access access,
                           od::Value factory = std::int64_t{0}) {
  od::EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.type = type;
  e.access = access;
  e.factory = std::move(factory);
  e.name = "test";
  return e;
}

inline std::vector<od::EntryInfo> entries() {
  using od::Access;
  using od::DataType;
  std::vector<od::EntryInfo> v = {
      entry(0x1001, 0, DataType::unsigned8, Access::ro),
      entry(0x1008, 0, DataType::visible_string, Access::const_, std::string("MC 5005")),
      entry(0x1010, 1, DataType::unsigned32, Access::rw),
      entry(0x1018, 4, DataType::unsigned32, Access::ro, std::int64_t{1}),
      entry(0x2320, 0, DataType::unsigned16, Access::ro),
      entry(0x2400, 3, DataType::unsigned8, Access::rw, std::int64_t{1}),
      entry(0x2400, 4, DataType::unsigned32, Access::rw, std::int64_t{0x00030000}),
      entry(0x2400, 5, DataType::unsigned8, Access::rw),
      entry(0x2400, 8, DataType::unsigned16, Access::rw),
      entry(0x3005, 0, DataType::unsigned8, Access::ro, std::int64_t{26}),
      entry(0x6040, 0, DataType::unsigned16, Access::rw),
      entry(0x6041, 0, DataType::unsigned16, Access::ro, std::int64_t{0x0040}),
      entry(0x6060, 0, DataType::integer8, Access::rw),
      entry(0x6064, 0, DataType::integer32, Access::ro),
      entry(0x60FF, 0, DataType::integer32, Access::rw),
  };
  v[7].validator = [](const od::ObjectDictionary&, std::optional<std::int64_t>, std::int64_t next) {
    return next > 1 ? od::AbortCode::invalid_value : od::AbortCode::none;  // net mode 0 … 1 (§6)
  };
  for (std::uint8_t s = 1; s <= 0x1A; ++s) v.push_back(entry(0x3005, s, DataType::integer32, Access::rw));
  return v;
}

inline std::unique_ptr<od::ObjectDictionary> make_dictionary() {
  return std::make_unique<od::ObjectDictionary>(entries());
}

// Sets a read-only entry as the drive would (origin internal).
inline void set(od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::int64_t v) {
  (void)od.write(index, sub, od::Value{v}, od::Origin::internal);
}

// "53 07 01 …" → bytes.
inline std::vector<std::uint8_t> bytes(std::string_view text) {
  std::vector<std::uint8_t> out;
  unsigned v = 0;
  int digits = 0;
  for (const char c : text) {
    int d = -1;
    if (c >= '0' && c <= '9') d = c - '0';
    if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
    if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    if (d < 0) continue;
    v = v * 16 + static_cast<unsigned>(d);
    if (++digits == 2) {
      out.push_back(static_cast<std::uint8_t>(v));
      v = 0;
      digits = 0;
    }
  }
  return out;
}

inline std::string chars(const std::vector<std::uint8_t>& b) { return std::string(b.begin(), b.end()); }
inline std::string wire(std::string_view text) { return chars(bytes(text)); }

// A request to node `node` built from its parts, as the hex of its wire bytes.
inline std::string request(std::uint8_t cmd, std::string_view data_hex, std::uint8_t node = 1) {
  return hex(encode(Frame{node, cmd, bytes(data_hex)}));
}

}  // namespace mcemu::faulhaber::test
