// od::Layout and od::preset_layout (drive/od/layout.hpp): dictionaries of equal presets share one
// immutable layout and nothing else — values, strings, hooks and listeners stay per dictionary.
#include "drive/od/layout.hpp"

#include <gtest/gtest.h>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/model_tables.hpp"
#include "tests/drive/od/preset_fixture.hpp"

namespace mcemu::od {
namespace {

using test::preset;

TEST(PresetLayout, EqualPresetsShareOneLayoutAndNoValues) {
  ObjectDictionary a(preset("MC349"));
  ObjectDictionary b(preset("MC349"));
  ASSERT_EQ(a.layout(), b.layout());
  EXPECT_EQ(a.info(0x6083, 0), b.info(0x6083, 0)) << "one description for both";

  const auto factory = *b.read_number(0x6083, 0);
  ASSERT_NE(factory, 1234);
  ASSERT_EQ(a.write(0x6083, 0, Value{std::int64_t{1234}}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(*a.read_number(0x6083, 0), 1234);
  EXPECT_EQ(*b.read_number(0x6083, 0), factory) << "a write to one dictionary leaves the other as it was";

  // A string entry: 1008h is read-only from outside, the drive writes it internally.
  const Handle name = a.handle(0x1008, 0);
  ASSERT_EQ(a.set(name, Value{std::string("renamed")}), AbortCode::none);
  EXPECT_EQ(a.value(name), Value{std::string("renamed")});
  EXPECT_EQ(b.value(name), b.info(name).factory);

  // Hooks belong to one dictionary.
  int calls = 0;
  a.on_write(0x6083, 0, [&](WriteRequest&) {
    ++calls;
    return AbortCode::none;
  });
  ASSERT_EQ(b.write(0x6083, 0, Value{std::int64_t{99}}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(calls, 0);
  ASSERT_EQ(a.write(0x6083, 0, Value{std::int64_t{99}}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(calls, 1);
}

TEST(PresetLayout, AnyDifferenceInThePresetOrVariantGivesItsOwnLayout) {
  const auto base = preset("MC349");
  auto serial = base;
  serial.identity.serial += 1;
  auto factory = base;
  factory.factory_values[{0x6083, 0}] = 777;
  ObjectDictionary a(base);
  ObjectDictionary b(serial);
  ObjectDictionary c(factory);
  EXPECT_NE(a.layout(), b.layout());
  EXPECT_NE(a.layout(), c.layout());
  EXPECT_EQ(*c.read_number(0x6083, 0), 777);
  EXPECT_NE(*a.read_number(0x6083, 0), 777);

  const auto same = preset_layout(base, 0, [&] { return build_entries(base); });
  EXPECT_EQ(same, a.layout());
  bool built = false;
  const auto other = preset_layout(base, 7, [&] {
    built = true;
    return build_entries(base);
  });
  EXPECT_TRUE(built) << "another variant of an equal preset is built";
  EXPECT_NE(other, a.layout());
}

TEST(PresetLayout, AnUnusedLayoutIsKeptForTheLastFewPresetsOnly) {
  auto first = preset("MC349");
  first.identity.serial = 0x1234;  // a preset no other test asks for
  std::weak_ptr<const Layout> weak;
  {
    ObjectDictionary od(first);
    weak = od.layout();
  }
  EXPECT_FALSE(weak.expired()) << "kept without a dictionary: the next drive of this preset reuses it";
  int builds = 0;
  auto again = preset_layout(first, 0, [&] {
    ++builds;
    return build_entries(first);
  });
  EXPECT_EQ(builds, 0);
  EXPECT_EQ(again, weak.lock());
  again.reset();
  // Four other presets asked for push it out of the kept ones; with no dictionary it is freed.
  for (std::uint32_t s = 1; s <= 4; ++s) {
    auto other = first;
    other.identity.serial = 0x1234 + s;
    ObjectDictionary od(other);
  }
  EXPECT_TRUE(weak.expired());
}

TEST(Layout, FactoryNumbersTypesAndStringSlotsFollowTheEntries) {
  const auto p = preset("MCFLAT");
  const Layout layout(build_entries(p));
  std::size_t strings = 0;
  for (Handle h = 0; h < layout.size(); ++h) {
    const auto& e = layout.info(h);
    EXPECT_EQ(layout.type(h), e.type);
    EXPECT_EQ(layout.locate(e.index, e.sub).value(), h);
    if (is_string(e.type)) {
      ASSERT_NE(layout.string_slot(h), Layout::k_no_string);
      EXPECT_EQ(layout.string_handles()[layout.string_slot(h)], h);
      EXPECT_FALSE(layout.unchecked(h));
      ++strings;
    } else {
      EXPECT_EQ(layout.string_slot(h), Layout::k_no_string);
      EXPECT_EQ(layout.factory_number(h), std::get<std::int64_t>(e.factory));
      EXPECT_EQ(layout.unchecked(h), !e.limits && !e.validator);
    }
  }
  EXPECT_EQ(strings, layout.string_handles().size());
  EXPECT_GT(strings, 0u);
}

TEST(Layout, AFactoryValueOfTheWrongKindIsABuildError) {
  EntryInfo e;
  e.index = 0x2000;
  e.type = DataType::visible_string;
  e.factory = std::int64_t{0};
  EXPECT_THROW(Layout({e}), std::logic_error);
}

}  // namespace
}  // namespace mcemu::od
