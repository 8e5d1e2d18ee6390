// Test harness for the drive core: a drive bundle built by the one fixture
// (tests/support/device_fixture.hpp), of which these tests step and drain only the core, with short
// helpers for SDO-like writes and reads. Everything runs in virtual time. The bundle's other parts
// (I/O functions, sessions, persistence) keep their write hooks but are never stepped; the I/O
// functions' inputs observer is detached, so the core is seen alone.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::core::test {

inline model::ModelPreset preset_of(const std::string& name) {
  auto p = model::find_preset(name);
  if (!p) throw std::invalid_argument("no preset " + name);
  return *p;
}

struct Drive {
  // power = false: the core stays unpowered until the test calls core.power_on().
  explicit Drive(const std::string& model = "MC349", const PlantConfig& config = {}, bool power = true)
      : fixture(model, options(config, power)), preset(fixture.preset()), od(fixture.od()), core(fixture.core()) {
    core.set_inputs_observer({});
  }

  // An SDO-origin write; returns the abort code.
  od::AbortCode write(std::uint16_t index, std::uint8_t sub, std::int64_t value) {
    const auto c = od.write(index, sub, od::Value{value}, od::Origin::sdo);
    collect();
    return c;
  }
  // A write that must succeed.
  void set(std::uint16_t index, std::uint8_t sub, std::int64_t value) {
    const auto c = write(index, sub, value);
    ASSERT_EQ(c, od::AbortCode::none) << std::hex << index << "." << int(sub) << " := " << std::dec << value;
  }
  void cw(std::uint16_t value) { set(0x6040, 0, value); }
  std::int64_t read(std::uint16_t index, std::uint8_t sub = 0) const {
    auto r = od.read_number(index, sub);
    EXPECT_TRUE(r.ok()) << std::hex << index << "." << int(sub);
    return r.ok() ? *r : 0;
  }
  std::uint16_t sw() const { return static_cast<std::uint16_t>(read(0x6041)); }
  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      core.step();
      collect();
    }
  }
  // Steps until pred() holds or max_ms passed; returns the number of steps taken (max_ms + 1 on timeout).
  template <typename Pred>
  std::uint64_t step_until(Pred pred, std::uint64_t max_ms) {
    for (std::uint64_t i = 1; i <= max_ms; ++i) {
      step();
      if (pred()) return i;
    }
    return max_ms + 1;
  }
  void collect() {
    auto e = core.drain_events();
    events.insert(events.end(), std::make_move_iterator(e.begin()), std::make_move_iterator(e.end()));
  }
  // Boot to SOD and enable: 6, 7, 0x0F (mode as given first, applied at once).
  void enable(std::int8_t mode = 1) {
    if (core.time_ms() == 0) step();
    set(0x6060, 0, mode);
    core.apply_mode_switch_now();
    cw(0x06);
    cw(0x07);
    cw(0x0F);
    collect();
  }
  template <typename E>
  std::vector<E> of() const {
    std::vector<E> out;
    for (const auto& e : events) {
      if (const E* p = std::get_if<E>(&e)) out.push_back(*p);
    }
    return out;
  }

  // Removes the persistence service's Store/Restore hooks, for tests that install their own.
  void release_store_hooks() { fixture.release_store_hooks(); }

  static mcemu::testing::DeviceOptions options(const PlantConfig& config, bool power) {
    mcemu::testing::DeviceOptions o;
    o.plant = config;
    o.power_on = power;
    o.keep_events = false;  // events are drained from the core here, into `events`
    return o;
  }

  mcemu::testing::DeviceFixture fixture;
  const model::ModelPreset& preset;
  od::ObjectDictionary& od;
  DriveCore& core;
  std::vector<Event> events;
};

// Shared by the homing and FAULHABER I/O tests (one definition: the unity build of the sanitizer
// tree puts several test sources into one translation unit, tests/CMakeLists.txt).
// A position no move of these tests reaches: the open end of a position switch's window.
inline constexpr std::int64_t k_far = std::numeric_limits<std::int32_t>::max();

// 6041h bits 10, 12 and 13: target reached, homing attained, homing error.
inline std::uint16_t homing_bits(const Drive& d) { return d.sw() & 0x3400; }

// Starts homing `method` (6098h) from operation enabled: 6040h 0x0F, then 0x1F.
inline void start_homing(Drive& d, std::int8_t method) {
  d.set(0x6098, 0, method);
  d.cw(0x0F);
  d.cw(0x1F);
}

}  // namespace mcemu::core::test
