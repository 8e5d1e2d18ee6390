// Test harness: one CANopen node on a preset (or extended test) dictionary, driven by SLCAN-style
// frame lines ("t63284041600000000000") at explicit simulated times. Frames out are returned as
// the SLCAN lines a client would see, concatenated, so the spec's examples are the expectations.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/model_tables.hpp"
#include "protocols/canopen/node.hpp"
#include "protocols/slcan/codec.hpp"

namespace mcemu::canopen::test {

using namespace std::chrono_literals;

// One step of a worked example: a request line and the response lines it must produce.
struct Exchange {
  std::string request;
  std::string response;
};

inline can::Frame frame(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  auto r = slcan::parse_line(line);
  if (!std::holds_alternative<slcan::Command>(r)) throw std::invalid_argument(std::string(line));
  return std::get<slcan::Command>(r).frame;
}

inline std::string lines(const std::vector<can::Frame>& frames) {
  std::string s;
  for (const auto& f : frames) s += slcan::encode_frame(f);
  return s;
}

inline od::EntryInfo test_entry(std::uint16_t index, std::uint8_t sub, od::DataType type, od::Access access,
                                od::Value factory = std::int64_t{0}) {
  od::EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.object_code = 7;
  e.type = type;
  e.access = access;
  e.factory = std::move(factory);
  e.cls = od::EntryClass::param;
  e.name = "test";
  e.object_name = "test";
  e.from_xdd = false;
  return e;
}

// The preset's entries plus test-only entries (slcan-canopen.md §12 "unit-test dictionary"):
// 2F00h rw string ("DOMAIN"), 2F01h wo U32, 2F02h ro string of 1000 bytes, 2F03h rw U8.
inline std::vector<od::EntryInfo> extended_entries(const model::ModelPreset& p) {
  auto v = od::build_entries(p);
  v.push_back(test_entry(0x2F00, 0, od::DataType::visible_string, od::Access::rw, std::string{}));
  v.push_back(test_entry(0x2F01, 0, od::DataType::unsigned32, od::Access::wo));
  std::string big(1000, 'x');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>('A' + i % 26);
  v.push_back(test_entry(0x2F02, 0, od::DataType::visible_string, od::Access::ro, big));
  v.push_back(test_entry(0x2F03, 0, od::DataType::unsigned8, od::Access::rw));
  return v;
}

struct Harness {
  explicit Harness(std::string_view model = "MC349", CanopenConfig config = {}, bool extended = false,
                   Node::Hooks hooks = {})
      : preset(*model::find_preset(model)),
        od(extended ? std::make_unique<od::ObjectDictionary>(extended_entries(preset))
                    : std::make_unique<od::ObjectDictionary>(preset)),
        node(std::make_unique<Node>(*od, config, std::move(hooks))) {}

  // Power on at t = 0 and run to the boot-up; returns what was sent (the boot-up frame).
  std::string boot() {
    node->power_on(now);
    return run_until(now + 10ms);
  }
  std::string send(std::string_view line) { return lines(node->on_frame(frame(line), now)); }
  // Calls advance() at every deadline up to t (inclusive); time then stands at t.
  std::string run_until(Millis t) {
    std::string out;
    for (int guard = 0; guard < 1000000; ++guard) {
      const auto d = node->next_deadline();
      if (!d || *d > t) break;
      now = std::max(now, *d);
      const auto frames = node->advance(now);
      for (const auto& f : frames) log.emplace_back(now, slcan::encode_frame(f));
      out += lines(frames);
    }
    now = t;
    return out;
  }
  std::string wait(Millis dt) { return run_until(now + dt); }
  // The server's 1 ms drive loop: advance() once per millisecond.
  std::string tick(int steps = 1) {
    std::string out;
    for (int i = 0; i < steps; ++i) {
      now += 1ms;
      const auto frames = node->advance(now);
      for (const auto& f : frames) log.emplace_back(now, slcan::encode_frame(f));
      out += lines(frames);
    }
    return out;
  }
  std::int64_t number(std::uint16_t index, std::uint8_t sub) const { return *od->read_number(index, sub); }
  void set(std::uint16_t index, std::uint8_t sub, std::int64_t v) {
    ASSERT_EQ(od->write(index, sub, od::Value{v}, od::Origin::internal), od::AbortCode::none);
  }

  model::ModelPreset preset;
  std::unique_ptr<od::ObjectDictionary> od;
  std::unique_ptr<Node> node;
  Millis now{0};
  std::vector<std::pair<Millis, std::string>> log;  // frames sent by advance(), with their time
};

// "t6328" + 16 hex digits of an SDO request with the given bytes.
inline std::string sdo(std::initializer_list<int> bytes) {
  static constexpr char k_hex[] = "0123456789ABCDEF";
  std::string s = "t6328";
  int n = 0;
  for (int b : bytes) {
    s.push_back(k_hex[(b >> 4) & 0xF]);
    s.push_back(k_hex[b & 0xF]);
    ++n;
  }
  for (; n < 8; ++n) s += "00";
  return s + "\r";
}

// "t5B28" + 16 hex digits + CR: the response line with the given bytes.
inline std::string resp(std::initializer_list<int> bytes) {
  std::string s = sdo(bytes);
  s.replace(1, 3, "5B2");
  return s;
}

// The abort response line for (index, sub, code).
inline std::string abort_line(std::uint16_t index, std::uint8_t sub, std::uint32_t code) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t5B2880%02X%02X%02X%02X%02X%02X%02X\r", index & 0xFF, index >> 8, sub, code & 0xFF,
                (code >> 8) & 0xFF, (code >> 16) & 0xFF, code >> 24);
  return buf;
}

}  // namespace mcemu::canopen::test
