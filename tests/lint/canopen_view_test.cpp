// The CANopen classification helpers (lint/canopen_view.cpp) on a real MC349 dictionary
// (node 50, the PDO set of slcan-canopen.md §9.1).
#include "lint/canopen_view.hpp"

#include <gtest/gtest.h>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::lint {
namespace {

struct Mc349 {
  od::ObjectDictionary od{*model::find_preset("MC349")};
  CanRequest frame(std::uint32_t id, bool rtr = false, std::uint8_t dlc = 8, std::uint8_t b0 = 0x40,
                   std::uint8_t b1 = 0) {
    const std::uint8_t data[8] = {b0, b1, 0, 0, 0, 0, 0, 0};
    return classify_can_frame(od, 123, 4, id, rtr, dlc, data, 50);
  }
};

TEST(ClassifyCanFrame, Kinds) {
  Mc349 m;
  EXPECT_EQ(m.frame(0x000, false, 2, 0x01, 50).kind, CanKind::nmt);
  EXPECT_EQ(m.frame(0x000, false, 2, 0x81, 0).kind, CanKind::nmt);     // all nodes
  EXPECT_EQ(m.frame(0x000, false, 2, 0x01, 51).kind, CanKind::other);  // another node
  EXPECT_EQ(m.frame(0x000, false, 3, 0x01, 50).kind, CanKind::other);  // DLC ≠ 2: ignored by the node
  EXPECT_EQ(m.frame(0x080, false, 0).kind, CanKind::sync);
  const CanRequest s = m.frame(0x632, false, 8, 0x2B);
  EXPECT_EQ(s.kind, CanKind::sdo);
  EXPECT_EQ(s.byte0, 0x2B);
  EXPECT_EQ(s.time, 123U);
  EXPECT_EQ(s.conn, 4U);
  EXPECT_EQ(m.frame(0x632, false, 7).kind, CanKind::other);  // DLC 7: no SDO request
  EXPECT_EQ(m.frame(0x732, true, 0).kind, CanKind::guarding);
  EXPECT_EQ(m.frame(0x123).kind, CanKind::other);
  EXPECT_EQ(m.frame(0x232, true, 2).kind, CanKind::other);  // remote frame on an RPDO id
}

TEST(ClassifyCanFrame, RpdosWithMotionAndLifeTime) {
  Mc349 m;
  ASSERT_EQ(m.od.read_number(0x1400, 1).value(), 0x232);
  for (std::uint32_t k = 0; k < 4; ++k) {
    const CanRequest r = m.frame(0x232 + 0x100 * k, false, 6);
    EXPECT_EQ(r.kind, CanKind::rpdo) << k;
    EXPECT_EQ(r.rpdo, k + 1);
    EXPECT_TRUE(r.motion) << k;  // every RPDO maps 6040h
  }
  EXPECT_EQ(m.frame(0x232, false, 2).life_time_ms, 0U);  // factory: no guarding
  ASSERT_EQ(m.od.write(0x100C, 0, od::Value{std::int64_t{100}}, od::Origin::sdo), od::AbortCode::none);
  ASSERT_EQ(m.od.write(0x100D, 0, od::Value{std::int64_t{3}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_EQ(m.frame(0x232, false, 2).life_time_ms, 300U);
  ASSERT_EQ(m.od.write(0x1017, 0, od::Value{std::int64_t{1000}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_EQ(m.frame(0x232, false, 2).life_time_ms, 0U);  // heartbeat producer on: guarding off
  // an invalid RPDO is no RPDO
  ASSERT_EQ(m.od.write(0x1400, 1, od::Value{std::int64_t{0x80000232}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_EQ(m.frame(0x232, false, 2).kind, CanKind::other);
}

TEST(PdoMappingWriteOf, ValidityOfThePdo) {
  Mc349 m;
  OdWrite w;
  w.time = 9;
  w.conn = 2;
  w.index = 0x1A00;
  w.sub = 0;
  w.result = od::AbortCode::read_only;
  auto p = pdo_mapping_write(m.od, w);
  ASSERT_TRUE(p);
  EXPECT_TRUE(p->pdo_valid);
  EXPECT_EQ(p->mapping_index, 0x1A00);
  EXPECT_EQ(p->result, od::AbortCode::read_only);
  EXPECT_EQ(p->time, 9U);
  ASSERT_EQ(m.od.write(0x1800, 1, od::Value{std::int64_t{0x800001B2}}, od::Origin::sdo), od::AbortCode::none);
  EXPECT_FALSE(pdo_mapping_write(m.od, w)->pdo_valid);
  w.index = 0x1800;  // not a mapping object
  EXPECT_FALSE(pdo_mapping_write(m.od, w));
  w.index = 0x1604;  // no 1404h on this model
  EXPECT_FALSE(pdo_mapping_write(m.od, w));
}

}  // namespace
}  // namespace mcemu::lint
