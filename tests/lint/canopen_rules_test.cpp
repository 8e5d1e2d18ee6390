// The CANopen rules (lint/canopen_rules.cpp), each triggered and each kept quiet (docs/lint.md §4.3).
#include <gtest/gtest.h>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

CanRequest sdo(Ms t, std::uint8_t byte0, Conn conn = 1) {
  CanRequest r;
  r.time = t;
  r.conn = conn;
  r.kind = CanKind::sdo;
  r.byte0 = byte0;
  return r;
}

CanRequest rpdo(Ms t, std::uint8_t n, bool motion = true, std::uint32_t life_time_ms = 0) {
  CanRequest r;
  r.time = t;
  r.conn = 1;
  r.kind = CanKind::rpdo;
  r.rpdo = n;
  r.motion = motion;
  r.life_time_ms = life_time_ms;
  return r;
}

CanRequest of_kind(Ms t, CanKind k) {
  CanRequest r;
  r.time = t;
  r.conn = 1;
  r.kind = k;
  return r;
}

void boot(Lint& l, Ms t, Nmt to = Nmt::pre_operational) {
  l.engine.observe(NmtChange{t, Nmt::initialising, Nmt::pre_operational});
  if (to != Nmt::pre_operational) l.engine.observe(NmtChange{t, Nmt::pre_operational, to});
}

// ---- SDO to a STOPPED node

TEST(CanopenSdoWhileStopped, RequestFires) {
  Lint l;
  boot(l, 0, Nmt::stopped);
  l.engine.observe(sdo(5, 0x40));
  ASSERT_TRUE(l.only(RuleId::canopen_sdo_while_stopped));
  EXPECT_EQ(l.found[0].origin, "canopen");
  // python-canopen's abort after its timeout is not a second finding, nor is the retry an overlap
  l.engine.observe(sdo(305, 0x80));
  l.engine.observe(sdo(306, 0x40));
  EXPECT_EQ(l.found.size(), 2U);
  EXPECT_TRUE(l.only(RuleId::canopen_sdo_while_stopped));
}

TEST(CanopenSdoWhileStopped, PreOperationalAndOperationalAreQuiet) {
  Lint l;
  boot(l, 0);
  l.engine.observe(sdo(1, 0x40));
  l.engine.observe(SdoAnswer{1, 0x4B});
  l.engine.observe(NmtChange{2, Nmt::pre_operational, Nmt::operational});
  l.engine.observe(sdo(3, 0x2B));
  l.engine.observe(SdoAnswer{3, 0x60});
  EXPECT_TRUE(l.found.empty());
}

// ---- SDO overlap

TEST(CanopenSdoOverlap, SecondRequestBeforeTheAnswerFires) {
  Lint l;
  boot(l, 0);
  l.engine.observe(sdo(1, 0x40, 1));
  l.engine.observe(sdo(1, 0x40, 2));  // another client on the same server channel
  ASSERT_TRUE(l.only(RuleId::canopen_sdo_overlap));
  EXPECT_EQ(l.found[0].conn, 2U);
}

TEST(CanopenSdoOverlap, AnsweredAbortedAndBlockTransfersAreQuiet) {
  Lint l;
  boot(l, 0);
  l.engine.observe(sdo(1, 0x40));
  l.engine.observe(SdoAnswer{1, 0x4B});
  l.engine.observe(sdo(2, 0x21));  // segmented download
  l.engine.observe(SdoAnswer{2, 0x60});
  l.engine.observe(sdo(3, 0x00));
  l.engine.observe(SdoAnswer{3, 0x20});
  l.engine.observe(sdo(4, 0x40));  // unanswered (a pending store), then the client's abort
  l.engine.observe(sdo(5, 0x80));
  l.engine.observe(sdo(6, 0xC6));  // block download initiate
  l.engine.observe(SdoAnswer{6, 0xA4});
  for (std::uint8_t seq = 1; seq <= 3; ++seq) l.engine.observe(sdo(7, seq));  // sub-block segments
  l.engine.observe(sdo(7, 0x84));                                             // the last one (c = 1)
  l.engine.observe(SdoAnswer{7, 0xA2});                                       // sub-block ack
  l.engine.observe(sdo(8, 0xC9));                                             // end request
  l.engine.observe(SdoAnswer{8, 0xA1});
  l.engine.observe(sdo(9, 0xA4));  // block upload initiate
  l.engine.observe(SdoAnswer{9, 0xC6});
  l.engine.observe(sdo(10, 0xA3));  // start
  l.engine.observe(SdoAnswer{10, 0x81});
  l.engine.observe(sdo(11, 0xA2));  // ack
  l.engine.observe(SdoAnswer{11, 0xC5});
  l.engine.observe(sdo(12, 0xA1));  // end response: nothing follows
  l.engine.observe(sdo(13, 0x40));
  EXPECT_TRUE(l.found.empty()) << l.found.size();
}

// ---- PDO mapping while valid

TEST(CanopenPdoMappingWhileValid, MappingWriteOnAValidPdoFires) {
  Lint l;
  l.engine.observe(PdoMappingWrite{1, 3, od::Origin::sdo, 0x1A00, 0, true, od::AbortCode::invalid_value});
  ASSERT_TRUE(l.only(RuleId::canopen_pdo_mapping_while_valid));
  EXPECT_NE(l.found[0].detail.find("1A00h.00 written while TPDO1 is valid (result 0x06090030)"), std::string::npos);
}

TEST(CanopenPdoMappingWhileValid, InvalidatedPdoIsQuiet) {
  Lint l;
  l.engine.observe(PdoMappingWrite{1, 3, od::Origin::sdo, 0x1601, 0, false, od::AbortCode::none});
  l.engine.observe(PdoMappingWrite{1, 0, od::Origin::internal, 0x1601, 1, true, od::AbortCode::none});
  EXPECT_TRUE(l.found.empty());
}

// ---- RPDO outside OPERATIONAL

TEST(CanopenRpdoNotOperational, RpdoInPreOperationalAndStoppedFires) {
  Lint l;
  boot(l, 0);
  l.engine.observe(rpdo(1, 1));
  l.engine.observe(NmtChange{2, Nmt::pre_operational, Nmt::stopped});
  l.engine.observe(rpdo(3, 4));
  ASSERT_EQ(l.count(RuleId::canopen_rpdo_not_operational), 2U);
  EXPECT_NE(l.found[0].detail.find("RPDO1 in PRE-OPERATIONAL"), std::string::npos);
  EXPECT_NE(l.found[1].detail.find("RPDO4 in STOPPED"), std::string::npos);
}

TEST(CanopenRpdoNotOperational, OperationalIsQuiet) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(rpdo(1, 1, false));
  EXPECT_TRUE(l.found.empty());
}

// ---- motion by RPDO without guarding

TEST(CanopenMotionWithoutGuarding, FiresOncePerOperationalStretch) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(rpdo(1, 1));
  l.engine.observe(rpdo(2, 1));
  EXPECT_EQ(l.count(RuleId::canopen_motion_without_guarding), 1U);
  l.engine.observe(NmtChange{3, Nmt::operational, Nmt::pre_operational});
  l.engine.observe(NmtChange{4, Nmt::pre_operational, Nmt::operational});
  l.engine.observe(rpdo(5, 3));
  EXPECT_EQ(l.count(RuleId::canopen_motion_without_guarding), 2U);
}

TEST(CanopenMotionWithoutGuarding, GuardingConfiguredButNoRtrFires) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(rpdo(1, 1, true, 300));
  EXPECT_TRUE(l.only(RuleId::canopen_motion_without_guarding));
}

TEST(CanopenMotionWithoutGuarding, QuietCases) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(of_kind(1, CanKind::guarding));
  l.engine.observe(rpdo(2, 1, true, 300));  // guarded
  l.engine.observe(rpdo(3, 2, false, 0));   // no motion object mapped
  EXPECT_TRUE(l.found.empty());
}

TEST(CanopenMotionWithoutGuarding, AResetForgetsTheGuardingRtr) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(of_kind(1, CanKind::guarding));
  l.engine.observe(NmtChange{2, Nmt::operational, Nmt::initialising});
  boot(l, 12, Nmt::operational);
  l.engine.observe(rpdo(13, 1, true, 300));
  EXPECT_TRUE(l.only(RuleId::canopen_motion_without_guarding));
}

// ---- traffic before the boot-up

TEST(CanopenTrafficBeforeBootup, FramesWhileInitialisingFire) {
  Lint l;
  boot(l, 0, Nmt::operational);
  l.engine.observe(NmtChange{5, Nmt::operational, Nmt::initialising});  // NMT reset node
  l.engine.observe(sdo(6, 0x40));
  l.engine.observe(of_kind(7, CanKind::nmt));
  EXPECT_EQ(l.count(RuleId::canopen_traffic_before_bootup), 2U);
  EXPECT_EQ(l.found.size(), 2U);
}

TEST(CanopenTrafficBeforeBootup, SyncAndFramesAfterTheBootupAreQuiet) {
  Lint l;
  boot(l, 0);
  l.engine.observe(NmtChange{5, Nmt::pre_operational, Nmt::initialising});
  l.engine.observe(of_kind(6, CanKind::sync));
  l.engine.observe(of_kind(6, CanKind::other));
  l.engine.observe(NmtChange{55, Nmt::initialising, Nmt::pre_operational});
  l.engine.observe(sdo(56, 0x40));
  EXPECT_TRUE(l.found.empty());
}

}  // namespace
}  // namespace mcemu::lint::test
