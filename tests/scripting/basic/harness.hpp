// Test rig of the MC BASIC interpreter: a small dictionary with the entries the programs use
// (faulhaber.md §8: 0x3005 variables, 0x2324.01 device status word, 0x2310/0x2311 I/O, the CiA 402
// objects of AN165's examples, plus entries of every type and a limited one), a fake SAVE store, the
// event log, and a toy drive (FakeDrive) that answers controlword writes inside the write as §7.1
// requires — enough for Examples A and B to run.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "scripting/basic/interpreter.hpp"
#include "scripting/basic/loader.hpp"
#include "scripting/basic/programs.hpp"

namespace mcemu::basic::test {

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

inline std::vector<od::EntryInfo> dictionary_entries() {
  using od::Access;
  using od::DataType;
  std::vector<od::EntryInfo> v;
  v.push_back(entry(0x1008, 0, DataType::visible_string, Access::const_, std::string("MC 5005")));
  v.push_back(entry(0x2310, 0x01, DataType::unsigned8, Access::rw));
  v.push_back(entry(0x2310, 0x02, DataType::unsigned8, Access::rw));
  v.push_back(entry(0x2310, 0x03, DataType::integer16, Access::rw, std::int64_t{1}));
  auto limited = entry(0x2310, 0x04, DataType::unsigned8, Access::rw);
  limited.limits = od::Range{0, 8};
  v.push_back(limited);
  v.push_back(entry(0x2310, 0x10, DataType::unsigned16, Access::rw));
  v.push_back(entry(0x2310, 0x11, DataType::unsigned8, Access::rw));
  v.push_back(entry(0x2311, 0x01, DataType::unsigned16, Access::ro));
  v.push_back(entry(0x2324, 0x01, DataType::unsigned32, Access::ro));
  v.push_back(entry(0x2324, 0x02, DataType::unsigned16, Access::rw, std::int64_t{200}));
  v.push_back(entry(0x2400, 0x04, DataType::unsigned32, Access::rw));
  v.push_back(entry(0x2400, 0x05, DataType::boolean, Access::rw));
  v.push_back(entry(0x3005, 0x00, DataType::unsigned8, Access::ro, std::int64_t{26}));
  for (std::uint8_t s = 1; s <= 26; ++s) v.push_back(entry(0x3005, s, DataType::integer32, Access::rw));
  v.push_back(entry(0x6040, 0, DataType::unsigned16, Access::rw));
  v.push_back(entry(0x6041, 0, DataType::unsigned16, Access::ro, std::int64_t{0x40}));
  v.push_back(entry(0x6060, 0, DataType::integer8, Access::rw));
  v.push_back(entry(0x6064, 0, DataType::integer32, Access::ro));
  v.push_back(entry(0x6068, 0, DataType::unsigned16, Access::rw));
  v.push_back(entry(0x607A, 0, DataType::integer32, Access::rw));
  v.push_back(entry(0x6083, 0, DataType::unsigned32, Access::rw));
  v.push_back(entry(0x6084, 0, DataType::unsigned32, Access::rw));
  v.push_back(entry(0x6098, 0, DataType::integer8, Access::rw));
  return v;
}

inline Program must_load(std::string_view text) {
  auto r = load(text);
  if (auto* e = std::get_if<LoadError>(&r)) {
    throw std::runtime_error("line " + std::to_string(e->line) + ": " + e->message);
  }
  return std::move(std::get<Program>(r));
}

// One interpreter on a fresh dictionary; time advances by one ms per step().
struct Rig {
  explicit Rig(std::uint32_t per_ms = 20, Settings s = {}) : od(dictionary_entries()) {
    s.statements_per_ms = per_ms;
    interp = std::make_unique<Interpreter>(od, store, s, [this](const Event& e) { events.push_back(e); });
  }
  void start(std::string_view text) {
    program = std::make_unique<Program>(must_load(text));
    interp->start(*program, 1);
  }
  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) interp->step(++now);
  }
  // Steps until the program no longer runs (at most `limit` steps); the steps taken.
  std::uint64_t run_to_end(std::uint64_t limit = 100000) {
    std::uint64_t n = 0;
    while (interp->running() && n < limit) {
      step();
      ++n;
    }
    return n;
  }
  std::int32_t var(char name) const {
    return static_cast<std::int32_t>(od.number(0x3005, static_cast<std::uint8_t>(name - 'a' + 1)));
  }
  void set_var(char name, std::int32_t v) {
    ASSERT_EQ(od.write(0x3005, static_cast<std::uint8_t>(name - 'a' + 1), od::Value{std::int64_t{v}}, od::Origin::sdo),
              od::AbortCode::none);
  }
  void set(std::uint16_t index, std::uint8_t sub, std::int64_t v) {
    ASSERT_EQ(od.set(od.handle(index, sub), od::Value{v}), od::AbortCode::none);
  }
  std::vector<Event> of_kind(EventKind k) const {
    std::vector<Event> out;
    for (const auto& e : events) {
      if (e.kind == k) out.push_back(e);
    }
    return out;
  }

  od::ObjectDictionary od;
  MemoryVariables store;
  std::vector<Event> events;
  std::unique_ptr<Interpreter> interp;
  std::unique_ptr<Program> program;
  std::uint64_t now = 0;
};

// A toy CiA 402 drive on the rig's dictionary: controlword writes take effect inside the write
// (§7.1), profile position moves at 100 increments/ms and set bit 10 once the position has been at
// the target for 6068h ms; a rising edge of bit 4 clears bit 10 in the same write even when the
// target equals the position; homing (6060h = 6) completes 50 ms after its start at position 0.
class FakeDrive {
 public:
  explicit FakeDrive(od::ObjectDictionary& od) : od_(od) {
    od_.on_write(0x6040, 0, [this](od::WriteRequest& r) {
      controlword(static_cast<std::uint16_t>(std::get<std::int64_t>(r.value)));
      return od::AbortCode::none;
    });
    publish();
  }
  // One ms of drive time (before the interpreter's step).
  void step() {
    if (state_ != 0x27) return;
    if (homing_ms_ > 0 && --homing_ms_ == 0) {
      pos_ = 0;
      bits_ |= 0x1400;  // homing attained + target reached
    }
    if (moving_) {
      const std::int64_t d = target_ - pos_;
      pos_ += d > 100 ? 100 : d < -100 ? -100 : d;
      if (pos_ == target_) {
        moving_ = false;
        settle_ms_ = od_.number(0x6068, 0);
        if (settle_ms_ == 0) bits_ |= 0x400;
      }
    } else if (settle_ms_ > 0 && --settle_ms_ == 0) {
      bits_ |= 0x400;
      ++moves_done_;
    }
    publish();
  }
  std::int64_t position() const { return pos_; }
  int moves_done() const { return moves_done_; }
  std::uint16_t state() const { return state_; }

 private:
  void controlword(std::uint16_t cw) {
    const bool rise4 = (cw & 0x10) && !(last_cw_ & 0x10);
    last_cw_ = cw;
    if ((cw & 0x0F) == 0x06) {
      if (state_ == 0x40 || state_ == 0x27) state_ = 0x21;
    } else if ((cw & 0x0F) == 0x0F) {
      if (state_ == 0x21 || state_ == 0x23) state_ = 0x27;
    } else if ((cw & 0x0F) == 0x07) {
      if (state_ == 0x21) state_ = 0x23;
    } else {
      state_ = 0x40;
      bits_ = 0;
      moving_ = false;
    }
    if (state_ == 0x27 && rise4) {
      if (od_.number(0x6060, 0) == 6) {
        bits_ &= ~0x1400;
        homing_ms_ = 50;
      } else {
        bits_ &= ~0x400;
        target_ = od_.number(0x607A, 0);
        moving_ = true;
      }
    }
    publish();
  }
  void publish() {
    od_.set(od_.handle(0x6041, 0), od::Value{std::int64_t{state_ | bits_}});
    od_.set(od_.handle(0x6064, 0), od::Value{pos_});
  }

  od::ObjectDictionary& od_;
  std::uint16_t state_ = 0x40;
  std::uint16_t bits_ = 0;
  std::uint16_t last_cw_ = 0;
  std::int64_t pos_ = 0;
  std::int64_t target_ = 0;
  bool moving_ = false;
  std::int64_t settle_ms_ = 0;
  int homing_ms_ = 0;
  int moves_done_ = 0;
};

}  // namespace mcemu::basic::test
