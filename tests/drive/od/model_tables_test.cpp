// Every preset's dictionary: sizes (object-dictionary.md §8.3), factory values (§7, models.md §3),
// which objects exist where, and the write limits of §5.
#include "drive/od/model_tables.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "tests/drive/od/preset_fixture.hpp"

namespace mcemu::od {
namespace {

using test::preset;

struct SizeCase {
  const char* model;
  std::size_t objects;
  std::size_t entries;
};

class PresetSizes : public ::testing::TestWithParam<SizeCase> {};

TEST_P(PresetSizes, MatchSpec) {
  const auto& c = GetParam();
  ObjectDictionary od(preset(c.model));
  std::set<std::uint16_t> objects;
  od.for_each([&](const EntryInfo& e, const Value&) { objects.insert(e.index); });
  EXPECT_EQ(objects.size(), c.objects);
  EXPECT_EQ(od.size(), c.entries);
}

INSTANTIATE_TEST_SUITE_P(Spec, PresetSizes,
                         ::testing::Values(SizeCase{"MC349", 122, 568}, SizeCase{"MC349_AE", 122, 575},
                                           SizeCase{"MC632", 122, 440}, SizeCase{"MC634", 122, 440},
                                           SizeCase{"MC636", 122, 440}, SizeCase{"PUSHTRACK", 122, 440},
                                           SizeCase{"MCFLAT", 124, 452}, SizeCase{"MCSHORT", 124, 452},
                                           SizeCase{"MCN23", 126, 476}));

class EveryPreset : public ::testing::TestWithParam<std::string_view> {};

TEST_P(EveryPreset, CommonFactoryValues) {
  const auto p = preset(GetParam());
  ObjectDictionary od(p);
  const auto n = [&](std::uint16_t i, std::uint8_t s) { return *od.read_number(i, s); };
  const auto str = [&](std::uint16_t i) { return std::get<std::string>(*od.read(i, 0)); };
  EXPECT_EQ(n(0x1000, 0), 0x00020192);
  EXPECT_EQ(str(0x1008), p.identity.device_name);
  EXPECT_EQ(str(0x1009), "V1.00");
  EXPECT_EQ(str(0x100A), p.identity.software_version);
  EXPECT_EQ(n(0x1018, 1), 0x053B);
  EXPECT_EQ(n(0x1018, 2), p.identity.product_code);
  EXPECT_EQ(n(0x1018, 4), 0x44444444);
  EXPECT_EQ(n(0x3404, 4), 0x44444444);
  EXPECT_EQ(n(0x1014, 0), 0xB2);
  EXPECT_EQ(n(0x1200, 1), 0x632);
  EXPECT_EQ(n(0x1200, 2), 0x5B2);
  EXPECT_EQ(n(0x1400, 1), 0x232);
  EXPECT_EQ(n(0x1800, 1), 0x1B2);
  EXPECT_EQ(n(0x1803, 1), 0x4B2);
  EXPECT_EQ(n(0x1802, 2), 0xFD);
  EXPECT_EQ(n(0x1600, 0), 1);
  EXPECT_EQ(n(0x1601, 0), 2);
  EXPECT_EQ(n(0x1603, 2), 0x60FF0020);
  for (std::uint8_t s = 1; s <= 3; ++s) {
    EXPECT_EQ(n(0x1010, s), 1);
    EXPECT_EQ(n(0x1011, s), 1);
  }
  EXPECT_EQ(n(0x1010, 0), 3);
  EXPECT_EQ(n(0x6502, 0), p.is_rabbit() ? 0x21 : 0x25);
  EXPECT_EQ(n(0x6073, 0), 1000);
  EXPECT_EQ(n(0x6081, 0), p.kind == model::Kind::linear ? 100000 : 1000);
  EXPECT_EQ(n(0x3401, 1), 100);
  EXPECT_EQ(n(0x3401, 2), 10);
  EXPECT_EQ(n(0x3401, 3), 1000);
  EXPECT_EQ(n(0x3401, 0x17), 20000);
  EXPECT_EQ(n(0x3401, 0x1A), 0);
  EXPECT_EQ(n(0x3404, 3), 50);
  EXPECT_EQ(n(0x5007, 1), 192);
  EXPECT_EQ(n(0x5007, 4), 150);
  EXPECT_EQ(n(0x5008, 3), 255);
  EXPECT_EQ(n(0x5008, 4), 0);
  EXPECT_EQ(n(0x6059, 1), 0);
  EXPECT_EQ(n(0x6059, 2), -200000);
  EXPECT_EQ(n(0x6059, 3), 100);
  EXPECT_EQ(n(0x607D, 1), 0);
  EXPECT_EQ(n(0x607D, 2), 0);
  EXPECT_EQ(n(0x6067, 0), 5000);
  EXPECT_EQ(n(0x6068, 0), 100);
  EXPECT_EQ(n(0x607F, 0), 2000);
  EXPECT_EQ(n(0x6083, 0), 1000);
  EXPECT_EQ(n(0x6085, 0), 1000);
  EXPECT_EQ(n(0x6099, 1), 1000);
  EXPECT_EQ(n(0x6099, 2), 200);
  EXPECT_EQ(n(0x60C5, 0), 20000);
  EXPECT_EQ(n(0x605A, 0), 1);
  EXPECT_EQ(n(0x6007, 0), 1);
  EXPECT_EQ(n(0x608F, 1), 65536);
  EXPECT_EQ(n(0x608F, 2), 1);
  EXPECT_EQ(n(0x6092, 1), 65536);
  EXPECT_EQ(n(0x6041, 0), 0x0040);
  EXPECT_EQ(n(0x67FF, 0), 0x00020192);
  EXPECT_EQ(n(0x3500, 0), 6);
  EXPECT_EQ(std::get<std::string>(*od.read(0x3500, 1)), "(empty)");
  EXPECT_EQ(n(0x3500, 5), 13);
  EXPECT_EQ(n(0x3500, 6), 0x23883CEF);
  EXPECT_EQ(n(0x3510, 0), 2);
  EXPECT_EQ(n(0x5006, 0), 5);
  EXPECT_EQ(str(0x6403), "");
  for (std::uint16_t i = 0x3511; i <= 0x351A; ++i) {
    EXPECT_EQ(n(i, 6), 200);
    EXPECT_EQ(n(i, 7), 2000);
    EXPECT_EQ(n(i, 9), 2000);
    EXPECT_EQ(n(i, 0x0A), 1000);
  }
  for (std::uint16_t i = 0x3611; i <= 0x3614; ++i) {
    EXPECT_EQ(n(i, 3), 1000);
    EXPECT_EQ(n(i, 4), -1000);
    EXPECT_EQ(n(i, 5), 100);
    EXPECT_EQ(n(i, 6), 100);
  }
  EXPECT_EQ(n(0x6075, 0), p.factory_values.at({0x6075, 0}));
  EXPECT_EQ(n(0x3401, 0x18), p.name == "MCN23" ? 100 : 1000);
}

TEST_P(EveryPreset, ObjectsOnlyWhereTheyBelong) {
  const auto p = preset(GetParam());
  ObjectDictionary od(p);
  const bool flat = p.base == model::Base::mcflat;
  const bool n23 = p.base == model::Base::mcn23;
  EXPECT_EQ(od.has_object(0x60A4), flat);
  EXPECT_EQ(od.has_object(0x60F4), flat || p.base == model::Base::mc6xx);
  EXPECT_EQ(od.has_object(0x3400), p.base == model::Base::mc349);
  EXPECT_EQ(od.has_object(0x2000), n23);
  EXPECT_EQ(od.has_object(0x5002), n23);
  EXPECT_EQ(od.has_object(0x3300), flat);
  EXPECT_EQ(od.has_object(0x60B8), !flat);
  EXPECT_TRUE(od.has_object(0x6062));
  EXPECT_TRUE(od.has_object(0x1400));
  EXPECT_TRUE(od.has_object(0x340B));
  EXPECT_TRUE(od.has_object(0x5007));
  EXPECT_EQ(od.read(0x1800, 4).error(), AbortCode::no_sub);
  EXPECT_EQ(od.read(0x6041, 1).error(), AbortCode::no_sub);
  EXPECT_EQ(od.info(0x3401, 0x1F) != nullptr, p.ae_extras || n23);
}

TEST_P(EveryPreset, Classes) {
  ObjectDictionary od(preset(GetParam()));
  const auto cls = [&](std::uint16_t i, std::uint8_t s) { return od.info(i, s)->cls; };
  EXPECT_EQ(cls(0x1000, 0), EntryClass::const_);
  EXPECT_EQ(cls(0x1008, 0), EntryClass::const_);
  EXPECT_EQ(cls(0x6041, 0), EntryClass::live);
  EXPECT_EQ(cls(0x6040, 0), EntryClass::proc);
  EXPECT_EQ(cls(0x6060, 0), EntryClass::proc);
  EXPECT_EQ(cls(0x607A, 0), EntryClass::proc);
  EXPECT_EQ(cls(0x60FE, 1), EntryClass::proc);
  EXPECT_EQ(cls(0x3510, 1), EntryClass::proc);
  EXPECT_EQ(cls(0x3510, 2), EntryClass::cmd);
  EXPECT_EQ(cls(0x1010, 1), EntryClass::cmd);
  EXPECT_EQ(cls(0x1011, 3), EntryClass::cmd);
  EXPECT_EQ(cls(0x1003, 0), EntryClass::cmd);
  EXPECT_EQ(cls(0x1017, 0), EntryClass::comm);
  EXPECT_EQ(cls(0x1800, 1), EntryClass::comm);
  EXPECT_EQ(cls(0x1029, 1), EntryClass::param);
  EXPECT_EQ(cls(0x6083, 0), EntryClass::param);
  EXPECT_EQ(cls(0x5007, 1), EntryClass::param);
  EXPECT_EQ(cls(0x3500, 4), EntryClass::param);
  EXPECT_EQ(cls(0x3401, 0x19), EntryClass::proc);
  EXPECT_EQ(cls(0x1A00, 1), EntryClass::const_);
  EXPECT_EQ(cls(0x6502, 0), EntryClass::const_);
}

TEST_P(EveryPreset, WriteLimits) {
  const auto p = preset(GetParam());
  ObjectDictionary od(p);
  const auto w = [&](std::uint16_t i, std::uint8_t s, std::int64_t v) { return od.write(i, s, Value{v}, Origin::sdo); };
  EXPECT_EQ(w(0x6060, 0, 2), AbortCode::invalid_value);
  EXPECT_EQ(w(0x6060, 0, 3), p.is_rabbit() ? AbortCode::invalid_value : AbortCode::none);
  EXPECT_EQ(w(0x6060, 0, 6), AbortCode::none);
  EXPECT_EQ(w(0x605A, 0, 3), AbortCode::invalid_value);
  EXPECT_EQ(w(0x605A, 0, 5), AbortCode::none);
  EXPECT_EQ(w(0x605B, 0, 2), AbortCode::invalid_value);
  EXPECT_EQ(w(0x605E, 0, 5), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3511, 1, 0x0C00), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3511, 1, 0x0B0A), AbortCode::none);
  EXPECT_EQ(w(0x3611, 1, 7), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3510, 2, 0x0B0C), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3510, 2, 0x0B00), AbortCode::none);
  EXPECT_EQ(w(0x3510, 2, 0x0A09), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1003, 0, 1), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1003, 0, 0), AbortCode::none);
  EXPECT_EQ(w(0x606D, 0, 0), AbortCode::value_too_low);
  EXPECT_EQ(w(0x6083, 0, 0), AbortCode::value_too_low);
  EXPECT_EQ(w(0x6083, 0, 250000), AbortCode::none) << "XDD maxima are not enforced";
  EXPECT_EQ(w(0x6092, 1, 0), AbortCode::value_too_low);
  EXPECT_EQ(w(0x6092, 1, 360), AbortCode::none);
  EXPECT_EQ(w(0x607A, 0, -2147483648LL), AbortCode::value_too_low);
  EXPECT_EQ(w(0x6067, 0, 2147483648LL), AbortCode::none);
  EXPECT_EQ(w(0x6067, 0, 2147483649LL), AbortCode::value_too_high);
  EXPECT_EQ(w(0x3404, 3, 0), AbortCode::value_too_low);
  EXPECT_EQ(w(0x3404, 3, 128), AbortCode::value_too_high);
  EXPECT_EQ(w(0x3401, 6, 2), AbortCode::value_too_high);
  EXPECT_EQ(w(0x1029, 1, 3), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1F51, 1, 4), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3500, 2, 3), AbortCode::invalid_value);
  EXPECT_EQ(w(0x3500, 4, 2), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1402, 2, 241), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1402, 2, 254), AbortCode::none);
  EXPECT_EQ(w(0x1801, 2, 252), AbortCode::none);
  EXPECT_EQ(w(0x1801, 2, 251), AbortCode::invalid_value);
  // COB-ID rules (slcan-canopen.md §9.2)
  EXPECT_EQ(w(0x1800, 1, 0x1B3), AbortCode::invalid_value) << "change while valid";
  EXPECT_EQ(w(0x1800, 3, 10), AbortCode::invalid_value) << "inhibit time only while invalid";
  EXPECT_EQ(w(0x1800, 1, 0x800001B2LL), AbortCode::none);
  EXPECT_EQ(w(0x1800, 3, 10), AbortCode::none);
  EXPECT_EQ(w(0x1800, 1, 0x1B3), AbortCode::none);
  EXPECT_EQ(w(0x1800, 1, 0x80000000LL | (1 << 29)), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1801, 1, 0x80000000LL | 0x700), AbortCode::none) << "restricted ids allowed while invalid";
  EXPECT_EQ(w(0x1801, 1, 0x701), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1005, 0, 0x40000080), AbortCode::invalid_value);
  EXPECT_EQ(w(0x1005, 0, 0x81), AbortCode::none);
  EXPECT_EQ(w(0x1014, 0, 0x80000000LL | 0xB2), AbortCode::none);
  if (od.has_object(0x60B8)) {
    EXPECT_EQ(w(0x60B8, 0, 0x00B0), AbortCode::invalid_value);
    EXPECT_EQ(w(0x60B8, 0, 0x1000), AbortCode::invalid_value);
    EXPECT_EQ(w(0x60B8, 0, 0x0A21), AbortCode::none);
  }
  if (p.base == model::Base::mcflat) {
    EXPECT_EQ(w(0x3300, 5, 181), AbortCode::value_too_high);
    EXPECT_EQ(w(0x3301, 1, 4), AbortCode::invalid_value);
  }
  if (p.base == model::Base::mcn23) {
    EXPECT_EQ(w(0x5000, 0, 5), AbortCode::none);
    EXPECT_EQ(w(0x5000, 0, 4), AbortCode::invalid_value);
  }
  // read-only and const entries
  EXPECT_EQ(w(0x6041, 0, 0), AbortCode::read_only);
  EXPECT_EQ(w(0x5007, 1, 10), AbortCode::read_only);
  EXPECT_EQ(w(0x1A00, 1, 0), AbortCode::read_only);
  EXPECT_EQ(od.write(0x1008, 0, Value{std::string("x")}, Origin::sdo), AbortCode::read_only);
}

TEST(ErrorHistory, ZeroClearsAndInternalMayCount) {
  ObjectDictionary od(preset("MC349"));
  ASSERT_EQ(od.write(0x1003, 1, Value{std::int64_t{0x7121}}, Origin::internal), AbortCode::none);
  ASSERT_EQ(od.write(0x1003, 0, Value{std::int64_t{1}}, Origin::internal), AbortCode::none);
  EXPECT_EQ(*od.read_number(0x1003, 0), 1);
  ASSERT_EQ(od.write(0x1003, 0, Value{std::int64_t{0}}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(*od.read_number(0x1003, 0), 0);
  EXPECT_EQ(*od.read_number(0x1003, 1), 0);
}

// The lookup (a hash of the keys, issue 26) finds every entry at its own handle, and tells an absent
// sub of an existing object (no_sub) from an absent object (no_object) for every index around each.
TEST_P(EveryPreset, LookupFindsEveryEntryAndClassifiesTheAbsent) {
  ObjectDictionary od(preset(GetParam()));
  std::vector<std::pair<std::uint16_t, std::uint8_t>> keys;
  od.for_each([&](const EntryInfo& e, const Value&) { keys.emplace_back(e.index, e.sub); });
  ASSERT_EQ(keys.size(), od.size());
  for (const auto& [index, sub] : keys) {
    const auto h = od.find(index, sub);
    ASSERT_TRUE(h) << std::hex << index << "." << int(sub);
    EXPECT_EQ(od.info(*h).index, index);
    EXPECT_EQ(od.info(*h).sub, sub);
  }
  const auto present = [&](std::uint16_t index, std::uint8_t sub) {
    return std::find(keys.begin(), keys.end(), std::pair{index, sub}) != keys.end();
  };
  for (const auto& [index, sub] : keys) {
    for (const std::uint16_t i :
         {static_cast<std::uint16_t>(index - 1), index, static_cast<std::uint16_t>(index + 1)}) {
      for (const std::uint8_t s : {std::uint8_t{0}, static_cast<std::uint8_t>(sub + 1), std::uint8_t{0xFF}}) {
        if (present(i, s)) continue;
        EXPECT_EQ(od.read(i, s).error(), od.has_object(i) ? AbortCode::no_sub : AbortCode::no_object)
            << std::hex << i << "." << int(s);
      }
    }
  }
}

// build_entries merges the XDD table with the sorted additions and looks objects up by binary
// search: every generated table must be strictly ascending by (index, sub).
TEST(XddTables, StrictlyAscending) {
  for (const auto base : {model::Base::mc349, model::Base::mc6xx, model::Base::mcflat, model::Base::mcn23}) {
    const auto table = xdd_table(base);
    ASSERT_FALSE(table.empty());
    for (std::size_t i = 1; i < table.size(); ++i) {
      EXPECT_LT(std::pair(table[i - 1].index, table[i - 1].sub), std::pair(table[i].index, table[i].sub))
          << model::to_string(base) << " row " << i;
    }
  }
}

TEST(Presets, UnknownNameAndRabbitSpecifics) {
  EXPECT_FALSE(model::find_preset("mc349"));
  EXPECT_FALSE(model::find_preset("MC999"));
  EXPECT_EQ(model::preset_names().size(), 9u);
  ObjectDictionary flat(preset("MCFLAT"));
  EXPECT_EQ(*flat.read_number(0x60A4, 0), 50000);
  EXPECT_EQ(*flat.read_number(0x3300, 7), 700);
  EXPECT_EQ(*flat.read_number(0x3301, 6), 100);
  EXPECT_EQ(*flat.read_number(0x3401, 4), 0);
  ObjectDictionary shrt(preset("MCSHORT"));
  EXPECT_EQ(*shrt.read_number(0x3300, 7), 150);
  ObjectDictionary ae(preset("MC349_AE"));
  EXPECT_EQ(*ae.read_number(0x3401, 0), 37);
  EXPECT_EQ(*ae.read_number(0x3401, 0x1C), 65536);
}

INSTANTIATE_TEST_SUITE_P(All, EveryPreset,
                         ::testing::Values("MC349", "MC349_AE", "MCN23", "MCFLAT", "MCSHORT", "MC632", "MC634", "MC636",
                                           "PUSHTRACK"));

}  // namespace
}  // namespace mcemu::od
