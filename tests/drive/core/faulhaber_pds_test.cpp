// FAULHABER drive differences of faulhaber.md §7.1–§7.3 on the drive core: statusword bits 6…0 per
// state, 0x0F from Ready to switch on, 6060h acting inside its write, the PP target-reached rule
// (bit 10 drops on every accepted set-point, rises after 6068h ms in 6067h), units and torque.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

Drive fh(const PlantConfig& config = {}) { return Drive("FH_MC5005", config); }

TEST(FaulhaberStatusword, BitsSixToZeroPerState) {
  Drive d = fh();
  EXPECT_EQ(d.sw(), 0x0000) << "not ready to switch on at t = 0";
  d.step();
  EXPECT_EQ(d.sw() & 0x7F, 0x40) << "switch on disabled: bit 5 is 0";
  d.cw(0x06);
  EXPECT_EQ(d.sw() & 0x7F, 0x21);
  d.cw(0x07);
  EXPECT_EQ(d.sw() & 0x7F, 0x23);
  d.cw(0x0F);
  EXPECT_EQ(d.sw() & 0x7F, 0x27);
  d.set(0x605A, 0, 6);  // stay in quick stop
  d.cw(0x02);
  EXPECT_EQ(d.sw() & 0x7F, 0x07);
  d.step(20);
  EXPECT_EQ(d.sw() & 0x7F, 0x07);
  d.cw(0x0F);
  EXPECT_EQ(d.sw() & 0x7F, 0x27) << "transition 16";
  d.core.inject(FaultCause::sensor);
  d.step(2);
  EXPECT_EQ(d.sw() & 0x7F, 0x08);
  d.core.clear(FaultCause::sensor);
  d.cw(0x00);
  d.cw(0x80);
  EXPECT_EQ(d.sw() & 0x7F, 0x40);
}

TEST(FaulhaberStatusword, BitFourNeverSetAndFactoryQuickStopDisables) {
  Drive d = fh();
  d.step();
  for (std::uint16_t cw : {0x06, 0x07, 0x0F, 0x02, 0x06, 0x0F}) {
    d.cw(cw);
    EXPECT_EQ(d.sw() & 0x10, 0) << std::hex << cw;
    d.step(50);
    EXPECT_EQ(d.sw() & 0x10, 0) << std::hex << cw;
  }
  // 605Ah = 2 (AN165: stop on the quick-stop ramp, then disable)
  Drive q = fh();
  q.enable(1);
  q.cw(0x02);
  EXPECT_EQ(q.sw() & 0x7F, 0x07);
  q.step(3);
  EXPECT_EQ(q.sw() & 0x7F, 0x40);
}

TEST(FaulhaberStatusword, EnableFromReadyToSwitchOnAtOnce) {
  Drive d = fh();
  d.step();
  d.cw(0x06);
  d.cw(0x0F);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled) << "inside the write";
  EXPECT_EQ(d.sw() & 0x7F, 0x27);
  const auto sc = d.of<StateChanged>();
  ASSERT_FALSE(sc.empty());
  EXPECT_EQ(sc.back().from, PdsState::ready_to_switch_on);
  EXPECT_EQ(sc.back().transition, 4);
}

TEST(FaulhaberModes, ModeOfOperationActsInsideTheWrite) {
  Drive d = fh();
  d.step();
  d.set(0x6060, 0, 6);
  EXPECT_EQ(d.read(0x6061), 6) << "switch on disabled";
  d.cw(0x06);
  d.cw(0x0F);
  d.set(0x6060, 0, 1);
  EXPECT_EQ(d.read(0x6061), 1) << "operation enabled";
  ASSERT_FALSE(d.of<ModeDisplayChanged>().empty());
  EXPECT_EQ(d.of<ModeDisplayChanged>().back().mode, 1);
  // the first set-point right after the mode write is a PP set-point, not lost in the mode switch
  d.set(0x607A, 0, 4096);
  d.cw(0x1F);
  EXPECT_EQ(d.of<SetpointAccepted>().size(), 1u);
  EXPECT_NE(d.sw() & 0x1000, 0);
  d.cw(0x0F);
  d.set(0x6060, 0, 3);
  EXPECT_EQ(d.read(0x6061), 3);
  for (std::int64_t bad : {-4, -3, -2, -1, 2, 4, 5, 7, 8, 9, 10}) {
    EXPECT_EQ(d.write(0x6060, 0, bad), od::AbortCode::invalid_value) << bad;
    EXPECT_EQ(d.read(0x6061), 3);
  }
}

TEST(FaulhaberProfilePosition, SetpointEqualToActualDropsBitTenAndRaisesItAfterTheWindowTime) {
  Drive d = fh();
  d.enable(1);
  d.step(50);
  ASSERT_EQ(d.read(0x6064), 0);
  ASSERT_NE(d.sw() & 0x0400, 0) << "held position counts as reached";
  d.set(0x607A, 0, 0);
  d.set(0x6068, 0, 500);
  d.cw(0x1F);
  EXPECT_EQ(d.sw() & 0x0400, 0) << "bit 10 cleared inside the 0x1F write";
  EXPECT_NE(d.sw() & 0x1000, 0);
  d.cw(0x0F);
  EXPECT_EQ(d.sw() & 0x0400, 0);
  const std::uint64_t ms = d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 2000);
  EXPECT_GE(ms, 500u);
  EXPECT_LE(ms, 501u);
  EXPECT_LE(std::llabs(d.read(0x6064) - d.read(0x607A)), d.read(0x6067));
}

TEST(FaulhaberProfilePosition, BitTenRisesOnlyAfterTheWindowTimeInsideTheWindow) {
  Drive d = fh();
  d.enable(1);
  d.set(0x6068, 0, 100);
  std::int64_t inside_since = -1;
  for (const std::int64_t target : {40000, 45000, 0}) {
    d.set(0x607A, 0, target);
    d.cw(0x1F);
    EXPECT_EQ(d.sw() & 0x0400, 0);
    d.cw(0x0F);
    for (int ms = 0; ms < 5000; ++ms) {
      d.step();
      const bool inside = std::llabs(d.read(0x6064) - target) <= d.read(0x6067);
      if (!inside) inside_since = -1;
      if (inside && inside_since < 0) inside_since = static_cast<std::int64_t>(d.core.time_ms());
      if (d.sw() & 0x0400) break;
    }
    ASSERT_NE(d.sw() & 0x0400, 0) << target;
    ASSERT_GE(inside_since, 0);
    EXPECT_GE(static_cast<std::int64_t>(d.core.time_ms()) - inside_since, 100) << target;
  }
}

TEST(FaulhaberUnits, IncrementsRpmAndRevolutionsPerSecondSquared) {
  Drive d = fh();
  d.set(0x6083, 0, 10);  // 10 rev/s² = 40960 inc/s²
  d.set(0x6084, 0, 10);
  d.set(0x6081, 0, 600);  // 600 min⁻¹ = 10 rev/s = 40960 inc/s
  d.enable(1);
  d.set(0x607A, 0, 4096 * 20);
  d.cw(0x1F);
  d.cw(0x0F);
  d.step(1000);  // accelerates for 1 s
  EXPECT_NEAR(static_cast<double>(d.read(0x606C)), 600, 5);
  EXPECT_NEAR(static_cast<double>(d.read(0x6064)), 20480, 200) << "½·a·t² = 2.5 rev";
  const std::uint64_t ms = d.step_until([&] { return (d.sw() & 0x0400) != 0; }, 5000);
  EXPECT_LT(ms, 5000u);
  EXPECT_LE(std::llabs(d.read(0x6064) - 81920), 20);
}

TEST(FaulhaberTorque, LimitsAreDirectionalAndActualTorqueIsPerMilleOfRated) {
  // pushing against a stop in homing −2 / −1 with a 1 s block-detection delay: the torque sits at
  // the limit of the direction until the homing takes the stop as its reference
  PlantConfig c;
  c.plant.set(&model::Plant::stops_inc, StopRange{-8192, 8192});
  Drive d = fh(c);
  d.set(0x60E0, 0, 600);
  d.set(0x60E1, 0, 300);
  d.set(0x2324, 0x02, 1000);
  d.enable(6);
  d.set(0x6098, 0, -2);
  d.cw(0x1F);
  d.step(800);
  EXPECT_EQ(d.core.raw_position_inc(), 8192);
  EXPECT_NEAR(static_cast<double>(d.read(0x6077)), 600, 2);
  EXPECT_NE(d.read(0x2324, 1) & (1 << 14), 0) << "torque limited";
  d.set(0x6072, 0, 100);
  d.step(5);
  EXPECT_NEAR(static_cast<double>(d.read(0x6077)), 100, 2) << "6072h bounds both directions";
  d.set(0x6072, 0, 3000);
  ASSERT_LE(d.step_until([&] { return (d.sw() & 0x1400) == 0x1400; }, 2000), 2000u);
  d.cw(0x0F);
  d.set(0x6098, 0, -1);
  d.cw(0x1F);
  d.step(800);
  EXPECT_EQ(d.core.raw_position_inc(), -8192);
  EXPECT_NEAR(static_cast<double>(d.read(0x6077)), -300, 2);
  EXPECT_EQ(d.core.state(), PdsState::operation_enabled);
  EXPECT_EQ(d.core.fault_bits(), 0u);
}

}  // namespace
}  // namespace mcemu::core
