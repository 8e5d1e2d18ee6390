// The FAULHABER dictionary (faulhaber.md §8): every object with type, access and factory value,
// the identity of each preset, the write limits, and no MovingCap manufacturer object.
#include "drive/od/faulhaber_table.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "tests/drive/od/preset_fixture.hpp"

namespace mcemu::od {
namespace {

using test::preset;

struct Row {
  std::uint16_t index;
  std::uint8_t sub;
  DataType type;
  Access access;
  std::int64_t factory;
};

using T = DataType;
using A = Access;

// faulhaber.md §6, §8 and the CiA 402 objects of §7 (factory values [choice] where the spec has none)
const Row k_rows[] = {
    {0x1000, 0, T::unsigned32, A::ro, 0x00020192},
    {0x1001, 0, T::unsigned8, A::ro, 0},
    {0x1003, 0, T::unsigned8, A::rw, 0},
    {0x1003, 4, T::unsigned32, A::ro, 0},
    {0x1018, 0, T::unsigned8, A::ro, 4},
    {0x1018, 1, T::unsigned32, A::ro, 0x147},
    {0x1018, 4, T::unsigned32, A::ro, 1},
    {0x2310, 0x01, T::unsigned8, A::rw, 0},
    {0x2310, 0x02, T::unsigned8, A::rw, 0},
    {0x2310, 0x03, T::integer16, A::rw, 1},
    {0x2310, 0x04, T::unsigned8, A::rw, 0},
    {0x2310, 0x10, T::unsigned16, A::rw, 0},
    {0x2310, 0x11, T::unsigned8, A::rw, 0},
    {0x2311, 0x01, T::unsigned16, A::ro, 0},
    {0x2311, 0x02, T::unsigned16, A::ro, 0},
    {0x2311, 0x03, T::unsigned16, A::ro, 0},
    {0x2311, 0x04, T::unsigned16, A::rw, 0xFFFF},
    {0x2320, 0x00, T::unsigned16, A::ro, 0},
    {0x2321, 0x01, T::unsigned16, A::rw, 0xFFFF},
    {0x2321, 0x02, T::unsigned16, A::rw, 0xFFFF},
    {0x2324, 0x01, T::unsigned32, A::ro, 0},
    {0x2324, 0x02, T::unsigned16, A::rw, 200},
    {0x2400, 0x03, T::unsigned8, A::rw, 1},
    {0x2400, 0x04, T::unsigned32, A::rw, 0x00030000},
    {0x2400, 0x05, T::unsigned8, A::rw, 0},
    {0x2400, 0x08, T::unsigned16, A::rw, 0},
    {0x3005, 0x00, T::unsigned8, A::ro, 26},
    {0x3005, 0x01, T::integer32, A::rw, 0},
    {0x3005, 0x09, T::integer32, A::rw, 0},
    {0x3005, 0x1A, T::integer32, A::rw, 0},
    {0x603F, 0, T::unsigned16, A::ro, 0},
    {0x6040, 0, T::unsigned16, A::rw, 0},
    {0x6041, 0, T::unsigned16, A::ro, 0x0040},
    {0x605A, 0, T::integer16, A::rw, 2},
    {0x6060, 0, T::integer8, A::rw, 0},
    {0x6061, 0, T::integer8, A::ro, 0},
    {0x6064, 0, T::integer32, A::ro, 0},
    {0x6067, 0, T::unsigned32, A::rw, 20},
    {0x6068, 0, T::unsigned16, A::rw, 20},
    {0x606C, 0, T::integer32, A::ro, 0},
    {0x6071, 0, T::integer16, A::rw, 0},
    {0x6072, 0, T::unsigned16, A::rw, 3000},
    {0x6077, 0, T::integer16, A::ro, 0},
    {0x607A, 0, T::integer32, A::rw, 0},
    {0x607C, 0, T::integer32, A::rw, 0},
    {0x6081, 0, T::unsigned32, A::rw, 1000},
    {0x6083, 0, T::unsigned32, A::rw, 1000},
    {0x6084, 0, T::unsigned32, A::rw, 1000},
    {0x6085, 0, T::unsigned32, A::rw, 3000},
    {0x608F, 1, T::unsigned32, A::rw, 4096},
    {0x6092, 1, T::unsigned32, A::rw, 4096},
    {0x6098, 0, T::integer8, A::rw, 0},
    {0x6099, 1, T::unsigned32, A::rw, 400},
    {0x6099, 2, T::unsigned32, A::rw, 40},
    {0x609A, 0, T::unsigned32, A::rw, 1000},
    {0x60E0, 0, T::unsigned16, A::rw, 3000},
    {0x60E1, 0, T::unsigned16, A::rw, 3000},
    {0x60FF, 0, T::integer32, A::rw, 0},
    {0x6502, 0, T::unsigned32, A::ro, 0x25},
};

class FaulhaberObject : public ::testing::TestWithParam<Row> {};

TEST_P(FaulhaberObject, TypeAccessFactory) {
  const Row& r = GetParam();
  ObjectDictionary od(preset("FH_MC5005"));
  const EntryInfo* e = od.info(r.index, r.sub);
  ASSERT_NE(e, nullptr) << std::hex << r.index << "." << int(r.sub);
  EXPECT_EQ(e->type, r.type);
  EXPECT_EQ(e->access, r.access);
  EXPECT_EQ(*od.read_number(r.index, r.sub), r.factory);
  EXPECT_FALSE(e->from_xdd);
}

INSTANTIATE_TEST_SUITE_P(Spec, FaulhaberObject, ::testing::ValuesIn(k_rows), [](const auto& p) {
  char name[16];
  std::snprintf(name, sizeof name, "x%04X_%02X", p.param.index, p.param.sub);
  return std::string(name);
});

struct IdentityCase {
  const char* model;
  const char* device_name;
  std::int64_t product;
  std::int64_t revision;
};

class FaulhaberIdentity : public ::testing::TestWithParam<IdentityCase> {};

TEST_P(FaulhaberIdentity, NamesAndCodes) {
  const auto& c = GetParam();
  const auto p = preset(c.model);
  EXPECT_EQ(p.family, model::Family::faulhaber);
  EXPECT_FALSE(p.has_io_functions());
  ObjectDictionary od(p);
  EXPECT_EQ(std::get<std::string>(*od.read(0x1008, 0)), c.device_name);
  EXPECT_EQ(std::get<std::string>(*od.read(0x100A, 0)), "0111.02O");
  EXPECT_EQ(*od.read_number(0x1018, 1), 0x147);
  EXPECT_EQ(*od.read_number(0x1018, 2), c.product);
  EXPECT_EQ(*od.read_number(0x1018, 3), c.revision);
  EXPECT_EQ(*od.read_number(0x1018, 4), 1);
  EXPECT_EQ(od.write(0x1008, 0, Value{std::string("x")}, Origin::sdo), AbortCode::read_only);
}

INSTANTIATE_TEST_SUITE_P(Spec, FaulhaberIdentity,
                         ::testing::Values(IdentityCase{"FH_MC5004", "MC 5004", 0, 1},
                                           IdentityCase{"FH_MC5005", "MC 5005", 0, 1},
                                           IdentityCase{"FH_MC5010", "MC 5010", 0, 1},
                                           IdentityCase{"FH_MCS", "MCS 3242 BX4 ET", 11601, 15}));

TEST(FaulhaberDictionary, ConfigOverridesReachTheFactoryImage) {
  auto p = preset("FH_MCS");
  p.identity.serial = 202400191;                  // config faulhaber.serial
  p.identity.device_name = "MCS custom";          // config faulhaber.device_name
  p.factory_values[{0x2400, 0x03}] = 5;           // config faulhaber.node_id
  p.factory_values[{0x2400, 0x04}] = 0x00830000;  // faulhaber.crc_check = false
  ObjectDictionary od(p);
  EXPECT_EQ(*od.read_number(0x1018, 4), 202400191);
  EXPECT_EQ(std::get<std::string>(*od.read(0x1008, 0)), "MCS custom");
  EXPECT_EQ(*od.read_number(0x2400, 3), 5);
  EXPECT_EQ(*od.read_number(0x2400, 4), 0x00830000);
}

TEST(FaulhaberDictionary, NoMovingCapManufacturerObjects) {
  ObjectDictionary od(preset("FH_MC5005"));
  std::set<std::uint16_t> objects;
  od.for_each([&](const EntryInfo& e, const Value&) { objects.insert(e.index); });
  for (const std::uint16_t i : objects) {
    const bool faulhaber = (i >= 0x2310 && i <= 0x2400) || i == 0x3005;
    if (i >= 0x2000 && i < 0x6000) {
      EXPECT_TRUE(faulhaber) << std::hex << i;
    }
  }
  for (const std::uint16_t i : {0x1002, 0x1400, 0x1800, 0x3300, 0x3401, 0x3404, 0x3500, 0x3510, 0x3511, 0x3611,
                                0x5000, 0x5006, 0x5007, 0x6059, 0x6073, 0x6078, 0x60B8, 0x60F2, 0x60FD, 0x60FE}) {
    EXPECT_FALSE(od.has_object(i)) << std::hex << i;
  }
  EXPECT_EQ(od.read_number(0x3401, 1).error(), AbortCode::no_object);
  // CiA 301 store / restore (1010h, 1011h) are the standard's, not MovingCap objects: the MC keeps
  // its parameters with "save" to 1010h.01 like every CiA 301 drive (POST /api/v1/store uses it).
  for (const std::uint16_t i : {0x1010, 0x1011}) {
    EXPECT_EQ(od.read_number(i, 0).value(), 3) << std::hex << i;
    EXPECT_EQ(od.info(i, 1)->access, Access::rw) << std::hex << i;
  }
}

struct LimitCase {
  std::uint16_t index;
  std::uint8_t sub;
  std::int64_t value;
  AbortCode expected;
};

class FaulhaberLimits : public ::testing::TestWithParam<LimitCase> {};

TEST_P(FaulhaberLimits, Write) {
  const auto& c = GetParam();
  ObjectDictionary od(preset("FH_MC5005"));
  EXPECT_EQ(od.write(c.index, c.sub, Value{c.value}, Origin::sdo), c.expected)
      << std::hex << c.index << "." << int(c.sub) << " := " << std::dec << c.value;
}

INSTANTIATE_TEST_SUITE_P(
    Spec, FaulhaberLimits,
    ::testing::Values(
        LimitCase{0x2400, 0x05, 0, AbortCode::none}, LimitCase{0x2400, 0x05, 1, AbortCode::none},
        LimitCase{0x2400, 0x05, 2, AbortCode::invalid_value}, LimitCase{0x2400, 0x05, 255, AbortCode::invalid_value},
        LimitCase{0x2400, 0x04, 0x00810000, AbortCode::none}, LimitCase{0x6060, 0, 1, AbortCode::none},
        LimitCase{0x6060, 0, 3, AbortCode::none}, LimitCase{0x6060, 0, 6, AbortCode::none},
        LimitCase{0x6060, 0, 0, AbortCode::none}, LimitCase{0x6060, 0, -1, AbortCode::invalid_value},
        LimitCase{0x6060, 0, -4, AbortCode::invalid_value}, LimitCase{0x6060, 0, 8, AbortCode::invalid_value},
        LimitCase{0x6060, 0, 10, AbortCode::invalid_value}, LimitCase{0x6060, 0, 2, AbortCode::invalid_value},
        LimitCase{0x6083, 0, 30000, AbortCode::none}, LimitCase{0x6083, 0, 30001, AbortCode::value_too_high},
        LimitCase{0x6083, 0, 0, AbortCode::value_too_low}, LimitCase{0x6085, 0, 32750, AbortCode::none},
        LimitCase{0x6085, 0, 32751, AbortCode::value_too_high}, LimitCase{0x2311, 0x01, 1, AbortCode::read_only},
        LimitCase{0x2320, 0x00, 1, AbortCode::read_only}, LimitCase{0x2324, 0x01, 1, AbortCode::read_only},
        LimitCase{0x3005, 0x00, 1, AbortCode::read_only}, LimitCase{0x3005, 0x09, -1, AbortCode::none},
        LimitCase{0x3005, 0x1B, 0, AbortCode::no_sub}, LimitCase{0x2310, 0x01, 256, AbortCode::value_too_high}));

TEST(FaulhaberDictionary, PresetNames) {
  ASSERT_EQ(model::faulhaber_preset_names().size(), 4u);
  EXPECT_EQ(model::all_preset_names().size(), model::preset_names().size() + 4);
  for (const auto name : model::faulhaber_preset_names()) {
    const auto p = model::find_preset(name);
    ASSERT_TRUE(p) << name;
    EXPECT_TRUE(p->is_faulhaber());
    EXPECT_EQ(p->name, name);
  }
  for (const auto name : model::preset_names()) {
    EXPECT_EQ(model::find_preset(name)->family, model::Family::movingcap) << name;
    EXPECT_TRUE(model::find_preset(name)->has_io_functions()) << name;
  }
  EXPECT_FALSE(model::find_preset("FH_MC5006"));
  EXPECT_FALSE(model::find_faulhaber_preset("MC349"));
}

}  // namespace
}  // namespace mcemu::od
