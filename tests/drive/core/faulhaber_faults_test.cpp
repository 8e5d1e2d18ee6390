// FAULHABER faults (faulhaber.md §6, §7.3, §8): EMCY code, error register (class bit + bit 0) and
// the bytes "code, register, 2320h LE, 0, 0, 0" for every core cause; 2320h, 1001h, 603Fh, 1003h
// and 2324h.01; the "error reset" EMCY; the emergency mask 2321h.01; the temperature warning; and
// catch-up = 1 ms stepping on a FAULHABER drive.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "tests/drive/core/core_fixture.hpp"
#include "tests/sim/trace_text.hpp"

namespace mcemu::core {
namespace {

using test::Drive;
using Bytes = std::array<std::uint8_t, 8>;

struct CauseCase {
  FaultCause cause;
  std::uint16_t code;
  std::uint8_t reg;
  std::uint16_t word;
  std::int64_t status_bit;  // 2324h.01 bit, -1 none
};

const CauseCase k_causes[] = {
    {FaultCause::over_voltage, 0x3210, 0x05, 0x0004, 18}, {FaultCause::under_voltage, 0x3220, 0x05, 0x0008, 19},
    {FaultCause::ack_error, 0x5000, 0x81, 0x0080, -1},    {FaultCause::over_temperature, 0x4310, 0x09, 0x0020, 17},
    {FaultCause::i2t, 0x4310, 0x09, 0x0020, 17},          {FaultCause::abort_connection, 0x8130, 0x11, 0x0800, -1},
    {FaultCause::stroke, 0x8611, 0x21, 0x0002, 5},        {FaultCause::motor_communication, 0x5000, 0x81, 0x0080, -1},
    {FaultCause::sensor, 0x7300, 0x81, 0x0040, -1},       {FaultCause::hw_sw_enable, 0xFF00, 0x81, 0x4000, -1},
    {FaultCause::over_current, 0x2300, 0x03, 0x0080, -1}, {FaultCause::external_torque, 0x8611, 0x21, 0x0002, 5},
    {FaultCause::needs_reset, 0x5000, 0x81, 0x0080, -1},
};

Bytes expected_bytes(std::uint16_t code, std::uint8_t reg, std::uint16_t word) {
  return {static_cast<std::uint8_t>(code & 0xFF),
          static_cast<std::uint8_t>(code >> 8),
          reg,
          static_cast<std::uint8_t>(word & 0xFF),
          static_cast<std::uint8_t>(word >> 8),
          0,
          0,
          0};
}

class FaulhaberCause : public ::testing::TestWithParam<CauseCase> {};

TEST_P(FaulhaberCause, EmcyAndObjects) {
  const auto& c = GetParam();
  Drive d("FH_MC5005");
  d.enable(1);
  d.events.clear();
  d.core.inject(c.cause);
  d.step(3);
  const auto emcys = d.of<Emcy>();
  const auto it = std::find_if(emcys.begin(), emcys.end(), [&](const Emcy& e) { return e.code == c.code; });
  ASSERT_NE(it, emcys.end()) << to_string(c.cause);
  EXPECT_EQ(it->bytes(), expected_bytes(c.code, c.reg, c.word)) << to_string(c.cause);
  EXPECT_EQ(emcys.front().code, c.code) << "the cause's EMCY comes first";
  EXPECT_EQ(d.read(0x1001) & c.reg, c.reg);
  EXPECT_EQ(d.read(0x2320) & c.word, c.word);
  EXPECT_EQ(d.read(0x603F), c.code);
  EXPECT_EQ(d.read(0x1003, 1), c.code);
  ASSERT_FALSE(d.of<FaultRaised>().empty());
  EXPECT_EQ(d.of<FaultRaised>()[0].code, c.code);
  if (c.status_bit >= 0) {
    EXPECT_NE(d.read(0x2324, 1) & (std::int64_t{1} << c.status_bit), 0) << to_string(c.cause);
  }
  EXPECT_EQ(d.sw() & 0x7F, 0x08);
}

INSTANTIATE_TEST_SUITE_P(Spec, FaulhaberCause, ::testing::ValuesIn(k_causes),
                         [](const auto& p) { return std::string(to_string(p.param.cause)); });

TEST(FaulhaberFaults, SpecExamplesAndErrorReset) {
  Drive d("FH_MC5005");
  d.enable(1);
  d.events.clear();
  d.core.set_supply_voltage(60);
  d.step(3);
  // faulhaber.md §5: EMCY 3210h, register 0x05, error word 0x0004
  ASSERT_EQ(d.of<Emcy>().size(), 1u);
  EXPECT_EQ(d.of<Emcy>()[0].bytes(), (Bytes{0x10, 0x32, 0x05, 0x04, 0x00, 0x00, 0x00, 0x00}));
  d.core.set_supply_voltage(24);
  d.events.clear();
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  ASSERT_EQ(d.of<Emcy>().size(), 1u);
  EXPECT_EQ(d.of<Emcy>()[0].bytes(), (Bytes{0, 0, 0, 0, 0, 0, 0, 0})) << "error reset";
  EXPECT_EQ(d.read(0x2320), 0);
  EXPECT_EQ(d.read(0x1001), 0);
  EXPECT_EQ(d.read(0x2324, 1) & (1 << 18), 0);
  // a real following error: the axis is held by an obstacle (faulhaber.md §5: 8611h, 0x21, 0x0002)
  d.events.clear();
  d.cw(0x06);
  d.cw(0x0F);
  d.set(0x6060, 0, 3);
  d.core.add_obstacle(Obstacle{2000, +1});
  d.set(0x60FF, 0, 300);
  EXPECT_LE(d.step_until([&] { return d.core.state() == PdsState::fault; }, 2000), 2000u);
  ASSERT_FALSE(d.of<Emcy>().empty());
  EXPECT_EQ(d.of<Emcy>()[0].bytes(), (Bytes{0x11, 0x86, 0x21, 0x02, 0x00, 0x00, 0x00, 0x00}));
  EXPECT_NE(d.read(0x2324, 1) & (1 << 5), 0);
}

TEST(FaulhaberFaults, EmergencyMaskSuppressesTheEmcyNotTheFault) {
  Drive d("FH_MC5005");
  d.set(0x2321, 1, 0xFFFF & ~0x0004);  // no EMCY for over-voltage
  d.enable(1);
  d.events.clear();
  d.core.inject(FaultCause::over_voltage);
  d.step(3);
  EXPECT_TRUE(d.of<Emcy>().empty());
  EXPECT_EQ(d.core.state(), PdsState::fault);
  EXPECT_EQ(d.read(0x2320), 0x0004);
  d.core.clear(FaultCause::over_voltage);
  d.cw(0x00);
  d.cw(0x80);
  ASSERT_EQ(d.of<Emcy>().size(), 1u) << "the error reset EMCY is always sent";
  EXPECT_EQ(d.of<Emcy>()[0].code, 0x0000);
}

TEST(FaulhaberFaults, TemperatureWarningThenOverTemperature) {
  Drive d("FH_MC5005");
  d.step();
  d.core.set_ambient_temperature(200);
  const auto warn_ms = d.step_until([&] { return d.core.temperature_warning(); }, 400000);
  ASSERT_LE(warn_ms, 400000u);
  EXPECT_EQ(round_half_away(d.core.temperature_c()), 100);
  ASSERT_EQ(d.of<Emcy>().size(), 1u);
  EXPECT_EQ(d.of<Emcy>()[0].bytes(), (Bytes{0xF0, 0x43, 0x03, 0x10, 0x00, 0x00, 0x00, 0x00}));
  EXPECT_EQ(d.read(0x2320), 0x0010);
  EXPECT_EQ(d.read(0x1001), 0x03);
  EXPECT_NE(d.read(0x2324, 1) & (1 << 16), 0);
  EXPECT_NE(d.sw() & 0x0080, 0) << "statusword warning bit";
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled) << "a warning is no fault";
  ASSERT_LE(d.step_until([&] { return d.core.state() == PdsState::fault; }, 400000), 400000u);
  ASSERT_EQ(d.of<Emcy>().size(), 2u);
  EXPECT_EQ(d.of<Emcy>()[1].bytes(), (Bytes{0x10, 0x43, 0x0B, 0x30, 0x00, 0x00, 0x00, 0x00}));
  EXPECT_NE(d.read(0x2324, 1) & (1 << 17), 0);
  d.core.set_ambient_temperature(20);
  ASSERT_LE(d.step_until([&] { return !d.core.temperature_warning(); }, 900000), 900000u);
  ASSERT_EQ(d.of<Emcy>().size(), 3u);
  EXPECT_EQ(d.of<Emcy>()[2].bytes(), (Bytes{0x00, 0x00, 0x09, 0x20, 0x00, 0x00, 0x00, 0x00}))
      << "the warning is gone, the error stays";
  d.cw(0x80);
  EXPECT_EQ(d.core.state(), PdsState::switch_on_disabled);
  EXPECT_EQ(d.read(0x2320), 0);
}

// catch-up (quiet_steps/skip) gives exactly what 1 ms stepping gives, across the temperature
// warning, an over-temperature fault and its reset
std::vector<std::string> run(bool catch_up) {
  Drive d("FH_MC5005");
  std::vector<std::string> out;
  const auto record = [&] {
    for (const auto& e : d.events) out.push_back(std::to_string(d.core.time_ms()) + " " + sim::test::event_text(e));
    d.events.clear();
    for (auto& line : sim::test::od_dump(d.od)) out.push_back(std::to_string(d.core.time_ms()) + " " + line);
  };
  const auto go_to = [&](std::uint64_t t) {
    while (d.core.time_ms() < t) {
      const std::uint64_t q = catch_up ? d.core.quiet_steps() : 0;
      if (q > 0) {
        d.core.skip(std::min(q, t - d.core.time_ms()));
      } else {
        d.step();
      }
    }
    d.collect();
    record();
  };
  go_to(10);
  d.core.set_ambient_temperature(200);
  for (std::uint64_t t = 10000; t <= 250000; t += 10000) go_to(t);
  d.core.set_ambient_temperature(20);
  for (std::uint64_t t = 260000; t <= 900000; t += 20000) go_to(t);
  d.cw(0x80);
  go_to(901000);
  return out;
}

TEST(FaulhaberQuiet, CatchUpEqualsOneMillisecondSteps) {
  const auto a = run(false);
  const auto b = run(true);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << i;
  EXPECT_TRUE(std::any_of(a.begin(), a.end(), [](const std::string& s) {
    return s.find("emcy 240 67") != std::string::npos;
  })) << "the scenario reaches the temperature warning (43F0h)";
}

}  // namespace
}  // namespace mcemu::core
