// Test rig for iofunc (iofunc.md §7): a drive bundle built by the one fixture
// (tests/support/device_fixture.hpp), of which the rig steps the drive alone — the IoFunctions engine,
// which steps the DriveCore — in virtual time, with the notation of the spec's test tables as short
// helpers: W (OD write, origin refgo), R (read), P (physical input level), step, until, enable,
// move_to, pulse. Scenario tables are lists of rows {what, action, expectation} run in order.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "iofunc/io_functions.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::iofunc::test {

struct Rig {
  // F349 (MC349) or FFLAT (MCFLAT): factory defaults, powered on, one step → Switch On Disabled.
  explicit Rig(const std::string& model = "MC349")
      : fixture(model), preset(fixture.preset()), od(fixture.od()), core(fixture.core()), io(fixture.io()) {
    step();
  }

  od::AbortCode try_write(std::uint16_t index, std::uint8_t sub, std::int64_t value) {
    return od.write(index, sub, od::Value{value}, od::Origin::refgo);
  }
  void W(std::uint16_t index, std::uint8_t sub, std::int64_t value) {
    const auto c = try_write(index, sub, value);
    ASSERT_EQ(c, od::AbortCode::none) << std::hex << index << "." << int(sub) << " := " << std::dec << value;
  }
  std::int64_t R(std::uint16_t index, std::uint8_t sub = 0) const {
    auto r = od.read_number(index, sub);
    EXPECT_TRUE(r.ok()) << std::hex << index << "." << int(sub);
    return r.ok() ? *r : 0;
  }
  void P(int n, bool level) { ASSERT_TRUE(core.set_external_input_level(n, level)) << "IN" << n; }
  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      fixture.step_drive();
      core.drain_events();
      auto d = io.drain_diagnostics();
      diagnostics.insert(diagnostics.end(), d.begin(), d.end());
    }
  }
  // Steps until pred() holds; fails the test if it does not within limit_ms.
  template <typename Pred>
  bool until(Pred pred, std::uint64_t limit_ms, const char* what = "condition") {
    for (std::uint64_t i = 0; i < limit_ms; ++i) {
      if (pred()) return true;
      step();
    }
    if (pred()) return true;
    ADD_FAILURE() << what << " not reached within " << limit_ms << " ms";
    return false;
  }

  std::uint16_t sw() const { return static_cast<std::uint16_t>(R(0x6041)); }
  std::uint32_t inputs() const { return static_cast<std::uint32_t>(R(0x60FD)); }
  std::uint32_t outputs() const { return static_cast<std::uint32_t>(R(0x60FE, 1)); }
  bool out(int k) const { return (outputs() >> (15 + k)) & 1; }
  bool reached() const { return (sw() & 0x0400) != 0; }

  // "enable": 6, 7, 15.
  void enable() {
    W(0x6040, 0, 6);
    W(0x6040, 0, 7);
    W(0x6040, 0, 15);
  }
  // Profile position mode, then an absolute single set-point (not waiting for the end).
  void start_move(std::int64_t p) {
    if (R(0x6061) != 1) {
      W(0x6060, 0, 1);
      step();
    }
    W(0x607A, 0, p);
    W(0x6040, 0, 0x2F);
    W(0x6040, 0, 0x3F);
  }
  // "move to p": start_move and until(6041h bit 10, 10 s).
  void move_to(std::int64_t p) {
    start_move(p);
    until([&] { return reached(); }, 10000, "target reached");
  }
  // "pulse INn": P(n,1), step(10), P(n,0), step(10).
  void pulse(int n) {
    P(n, true);
    step(10);
    P(n, false);
    step(10);
  }

  mcemu::testing::DeviceFixture fixture;  // powered on by the bundle
  const model::ModelPreset& preset;
  od::ObjectDictionary& od;
  core::DriveCore& core;
  IoFunctions& io;
  std::vector<Diagnostic> diagnostics;
};

// The state bits of 6041h (CiA 402 state machine), for tests that compare the state alone.
inline constexpr std::uint16_t k_state_mask = 0x006F;

// One row of a scenario table: an action, then the expectation checked after it.
struct Row {
  std::string what;
  std::function<void(Rig&)> action;
  std::function<void(Rig&)> expect;
};

inline void run_rows(Rig& rig, const std::vector<Row>& rows) {
  for (const Row& r : rows) {
    SCOPED_TRACE(r.what);
    if (r.action) r.action(rig);
    if (::testing::Test::HasFatalFailure()) return;
    if (r.expect) r.expect(rig);
  }
}

}  // namespace mcemu::iofunc::test
