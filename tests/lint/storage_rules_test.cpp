// The storage and script rules (lint/storage_rules.cpp): store rate, store while moving, script
// loops that never wait, stores in a script loop (docs/lint.md §4.2, §4.5).
#include "lint/storage_rules.hpp"

#include <gtest/gtest.h>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

constexpr std::int64_t k_save = 0x65766173;
constexpr std::int64_t k_load = 0x64616F6C;
constexpr Ms k_min = 60000;

OdWrite store(Ms t, od::Origin origin = od::Origin::sdo, std::uint16_t sw = 0x0027) {
  OdWrite w = write(t, 0x1010, k_save, sw, 1, origin);
  w.sub = 1;
  w.result = od::AbortCode::pending;  // a store answers when the file is durable
  return w;
}

Config with_limit(std::uint32_t n) {
  Config c;
  c.max_stores_per_hour = n;
  return c;
}

TEST(FlashKindOf, Signatures) {
  OdWrite w = store(0);
  EXPECT_EQ(flash_kind_of(w), FlashKind::parameters);
  w.sub = 3;
  EXPECT_EQ(flash_kind_of(w), FlashKind::parameters);
  w.value = 1;  // wrong signature: nothing is stored (persistence.md §3)
  EXPECT_EQ(flash_kind_of(w), std::nullopt);
  w = store(0);
  w.result = od::AbortCode::cannot_store;
  EXPECT_EQ(flash_kind_of(w), std::nullopt);
  w = write(0, 0x1011, k_load, 0x40);
  w.sub = 1;
  EXPECT_EQ(flash_kind_of(w), FlashKind::factory_reset);
  w = write(0, 0x3010, k_save, 0x40);
  w.sub = 1;
  EXPECT_EQ(flash_kind_of(w), FlashKind::motor);
  w.sub = 2;
  EXPECT_EQ(flash_kind_of(w), std::nullopt);
}

TEST(StoreRate, MoreThanTheLimitWithinAnHourFires) {
  Lint l(with_limit(3));
  for (Ms t : {0 * k_min, 10 * k_min, 20 * k_min}) l.engine.observe(store(t));
  EXPECT_TRUE(l.found.empty());
  l.engine.observe(store(59 * k_min));
  ASSERT_TRUE(l.only(RuleId::storage_store_rate));
  EXPECT_NE(l.found[0].detail.find("4 stores within 3540 s"), std::string::npos);
}

TEST(StoreRate, SpreadOverMoreThanAnHourIsQuiet) {
  Lint l(with_limit(3));
  for (Ms t : {0 * k_min, 20 * k_min, 40 * k_min, 60 * k_min, 80 * k_min}) l.engine.observe(store(t));
  EXPECT_TRUE(l.found.empty());
}

TEST(StoreRate, CountsFlashWritesOfEveryKind) {
  Lint l(with_limit(1));
  l.engine.observe(FlashWrite{0, 0, od::Origin::web, FlashKind::program});
  l.engine.observe(store(1000));
  EXPECT_TRUE(l.only(RuleId::storage_store_rate));
}

TEST(StoreRate, DriveTimeRestartingAtPowerOnStillCounts) {
  Lint l(with_limit(2));
  l.engine.observe(store(5000));
  l.engine.observe(store(6000));
  l.engine.observe(PowerOn{0, 0, 0, 0, 0});  // drive time restarts at 0 (drive-core.md §4.4)
  l.engine.observe(store(100));
  EXPECT_TRUE(l.only(RuleId::storage_store_rate));
}

TEST(StoreWhileMoving, StoreWithBit8Fires) {
  Lint l;
  l.drive_at(0, 0x0127);
  l.engine.observe(store(1, od::Origin::refgo, 0x0127));
  ASSERT_TRUE(l.only(RuleId::storage_store_while_moving));
  EXPECT_EQ(l.found[0].origin, "refgo");
}

TEST(StoreWhileMoving, StandstillAndWrongSignatureAreQuiet) {
  Lint l;
  l.drive_at(0, 0x0427);
  l.engine.observe(store(1));
  l.drive_at(2, 0x0127);
  OdWrite w = store(3, od::Origin::sdo, 0x0127);
  w.value = 12345;
  l.engine.observe(w);
  EXPECT_TRUE(l.found.empty());
}

TEST(ScriptBusyLoop, OncePerStretchWithoutAWait) {
  Lint l;
  l.engine.observe(ScriptLoop{10, ScriptKind::code, 999});
  EXPECT_TRUE(l.found.empty());
  l.engine.observe(ScriptLoop{11, ScriptKind::code, 1000});
  l.engine.observe(ScriptLoop{12, ScriptKind::code, 5000});  // the same stretch
  ASSERT_TRUE(l.only(RuleId::script_busy_loop));
  EXPECT_EQ(l.found.size(), 1U);
  EXPECT_EQ(l.found[0].origin, "script");
  l.engine.observe(ScriptLoop{13, ScriptKind::code, 3});  // it waited
  l.engine.observe(ScriptLoop{14, ScriptKind::code, 2000});
  EXPECT_EQ(l.count(RuleId::script_busy_loop), 2U);
}

TEST(ScriptBusyLoop, BasicHasItsOwnLimit) {
  Config c;
  c.basic_statements_without_wait = 100;
  Lint l(c);
  l.engine.observe(ScriptLoop{1, ScriptKind::basic, 99});
  EXPECT_TRUE(l.found.empty());
  l.engine.observe(ScriptLoop{2, ScriptKind::basic, 100});
  ASSERT_TRUE(l.only(RuleId::script_busy_loop));
  EXPECT_EQ(l.found[0].origin, "basic");
}

TEST(ScriptFlashWriteInLoop, SecondScriptStoreWithinTheWindowFires) {
  Lint l;
  l.engine.observe(store(0, od::Origin::script));
  l.engine.observe(FlashWrite{1500, 0, od::Origin::script, FlashKind::program});  // MC BASIC SAVE
  EXPECT_EQ(l.count(RuleId::script_flash_write_in_loop), 1U);
}

TEST(ScriptFlashWriteInLoop, QuietCases) {
  Lint l;
  l.engine.observe(store(0, od::Origin::script));
  l.engine.observe(store(61000, od::Origin::script));  // outside the 60 s window
  l.engine.observe(store(62000, od::Origin::sdo));     // not a script
  EXPECT_TRUE(l.found.empty());
}

TEST(ScriptFlashWriteInLoop, TimingOffSwitchesItOff) {
  Config c;
  c.timing = false;
  Lint l(c);
  l.engine.observe(store(0, od::Origin::script));
  l.engine.observe(store(0, od::Origin::script));
  EXPECT_EQ(l.count(RuleId::script_flash_write_in_loop), 0U);
}

}  // namespace
}  // namespace mcemu::lint::test
