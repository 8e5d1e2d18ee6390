// Black-box tests of od::ObjectDictionary: the check order and abort codes of
// object-dictionary.md §4, value conversion §3.2, SDO length rules §3.1, hooks, bulk load.
#include "drive/od/dictionary.hpp"

#include <gtest/gtest.h>

#include <array>

#include "drive/od/settings_cache.hpp"

namespace mcemu::od {
namespace {

EntryInfo entry(std::uint16_t index, std::uint8_t sub, DataType type, Access access, Value factory = std::int64_t{0}) {
  EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.object_code = sub == 0 ? 7 : 9;
  e.type = type;
  e.access = access;
  e.factory = std::move(factory);
  e.cls = EntryClass::param;
  e.name = "test";
  return e;
}

std::vector<EntryInfo> test_entries() {
  std::vector<EntryInfo> v;
  v.push_back(entry(0x2000, 0, DataType::unsigned8, Access::rw));
  v.push_back(entry(0x2001, 0, DataType::integer8, Access::rw));
  v.push_back(entry(0x2002, 0, DataType::unsigned16, Access::rw));
  v.push_back(entry(0x2003, 0, DataType::integer16, Access::rw));
  v.push_back(entry(0x2004, 0, DataType::unsigned32, Access::rw));
  v.push_back(entry(0x2005, 0, DataType::integer32, Access::rw));
  v.push_back(entry(0x2006, 0, DataType::visible_string, Access::const_, Value{std::string("MC349_ETH_RE")}));
  v.push_back(entry(0x2007, 0, DataType::unsigned32, Access::ro, std::int64_t{7}));
  v.push_back(entry(0x2008, 0, DataType::unsigned32, Access::wo));
  v.push_back(entry(0x2009, 0, DataType::unsigned32, Access::const_, std::int64_t{9}));
  // a record with a gap at sub 2
  v.push_back(entry(0x2100, 0, DataType::unsigned8, Access::ro, std::int64_t{3}));
  v.push_back(entry(0x2100, 1, DataType::integer32, Access::rw));
  v.push_back(entry(0x2100, 3, DataType::integer32, Access::rw));
  auto lim = entry(0x2200, 0, DataType::unsigned32, Access::rw, std::int64_t{5});
  lim.limits = Range{1, 100};
  v.push_back(lim);
  auto set = entry(0x2201, 0, DataType::integer16, Access::rw, std::int64_t{1});
  set.validator = [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t x) {
    return x == 0 || x == 1 || x == 6 ? AbortCode::none : AbortCode::invalid_value;
  };
  v.push_back(set);
  auto tol = entry(0x2202, 0, DataType::unsigned16, Access::rw);
  tol.length_tolerant = true;
  v.push_back(tol);
  return v;
}

struct WriteCase {
  std::uint16_t index;
  std::uint8_t sub;
  Value value;
  Origin origin;
  AbortCode expected;
};

class WriteTable : public ::testing::TestWithParam<WriteCase> {};

TEST_P(WriteTable, FirstFailingCheckDecides) {
  ObjectDictionary od(test_entries());
  const auto& c = GetParam();
  const auto before = od.read(c.index, c.sub);
  EXPECT_EQ(od.write(c.index, c.sub, c.value, c.origin), c.expected);
  if (c.expected != AbortCode::none && before) {
    EXPECT_EQ(*od.read(c.index, c.sub), *before) << "a refused write changes nothing";
  }
}

using S = std::string;
INSTANTIATE_TEST_SUITE_P(
    Checks, WriteTable,
    ::testing::Values(WriteCase{0x3000, 0, std::int64_t{1}, Origin::sdo, AbortCode::no_object},
                      WriteCase{0x2000, 1, std::int64_t{1}, Origin::sdo, AbortCode::no_sub},
                      WriteCase{0x2100, 2, std::int64_t{1}, Origin::sdo, AbortCode::no_sub},
                      WriteCase{0x2100, 4, std::int64_t{1}, Origin::sdo, AbortCode::no_sub},
                      WriteCase{0x2100, 0, std::int64_t{1}, Origin::refgo, AbortCode::read_only},
                      WriteCase{0x2007, 0, std::int64_t{1}, Origin::web, AbortCode::read_only},
                      WriteCase{0x2009, 0, std::int64_t{1}, Origin::script, AbortCode::read_only},
                      WriteCase{0x2006, 0, std::int64_t{1}, Origin::sdo, AbortCode::read_only},
                      WriteCase{0x2007, 0, std::int64_t{1}, Origin::internal, AbortCode::none},
                      WriteCase{0x2000, 0, S("x"), Origin::web, AbortCode::type_mismatch},
                      WriteCase{0x2000, 0, std::int64_t{255}, Origin::sdo, AbortCode::none},
                      WriteCase{0x2000, 0, std::int64_t{256}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2000, 0, std::int64_t{-1}, Origin::sdo, AbortCode::value_too_low},
                      WriteCase{0x2001, 0, std::int64_t{-128}, Origin::sdo, AbortCode::none},
                      WriteCase{0x2001, 0, std::int64_t{-129}, Origin::sdo, AbortCode::value_too_low},
                      WriteCase{0x2001, 0, std::int64_t{128}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2002, 0, std::int64_t{65536}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2003, 0, std::int64_t{-32769}, Origin::sdo, AbortCode::value_too_low},
                      WriteCase{0x2004, 0, std::int64_t{4294967295LL}, Origin::sdo, AbortCode::none},
                      WriteCase{0x2004, 0, std::int64_t{-1}, Origin::script, AbortCode::none},
                      WriteCase{0x2004, 0, std::int64_t{-2147483648LL}, Origin::script, AbortCode::none},
                      WriteCase{0x2004, 0, std::int64_t{-2147483649LL}, Origin::script, AbortCode::value_too_low},
                      WriteCase{0x2004, 0, std::int64_t{4294967296LL}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2005, 0, std::int64_t{2147483648LL}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2200, 0, std::int64_t{0}, Origin::sdo, AbortCode::value_too_low},
                      WriteCase{0x2200, 0, std::int64_t{101}, Origin::sdo, AbortCode::value_too_high},
                      WriteCase{0x2200, 0, std::int64_t{100}, Origin::sdo, AbortCode::none},
                      WriteCase{0x2200, 0, std::int64_t{0}, Origin::internal, AbortCode::value_too_low},
                      WriteCase{0x2201, 0, std::int64_t{2}, Origin::sdo, AbortCode::invalid_value},
                      WriteCase{0x2201, 0, std::int64_t{6}, Origin::sdo, AbortCode::none},
                      WriteCase{0x2201, 0, std::int64_t{40000}, Origin::sdo, AbortCode::value_too_high}));

TEST(Dictionary, ReadChecks) {
  ObjectDictionary od(test_entries());
  EXPECT_EQ(od.read(0x3000, 0).error(), AbortCode::no_object);
  EXPECT_EQ(od.read(0x2000, 1).error(), AbortCode::no_sub);
  EXPECT_EQ(od.read(0x2008, 0).error(), AbortCode::write_only);
  EXPECT_EQ(od.read_number(0x2006, 0).error(), AbortCode::type_mismatch);
  EXPECT_EQ(std::get<std::string>(*od.read(0x2006, 0)), "MC349_ETH_RE");
  EXPECT_EQ(*od.read_number(0x2007, 0), 7);
  EXPECT_EQ(od.write(0x2008, 0, std::int64_t{3}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(od.check_upload(0x2008, 0), AbortCode::write_only);
}

TEST(Dictionary, UnsignedNegativeIsStoredAsBitPattern) {
  ObjectDictionary od(test_entries());
  ASSERT_EQ(od.write(0x2004, 0, std::int64_t{-1}, Origin::script), AbortCode::none);
  EXPECT_EQ(*od.read_number(0x2004, 0), 4294967295LL);
}

std::vector<std::byte> bytes(std::initializer_list<int> b) {
  std::vector<std::byte> v;
  for (int x : b) v.push_back(static_cast<std::byte>(x));
  return v;
}

struct SdoCase {
  std::uint16_t index;
  std::vector<std::byte> data;
  SdoLength length;
  AbortCode expected;
  std::int64_t stored;  // value read back when accepted
};

class SdoLengthTable : public ::testing::TestWithParam<SdoCase> {};

TEST_P(SdoLengthTable, LengthRules) {
  ObjectDictionary od(test_entries());
  const auto& c = GetParam();
  EXPECT_EQ(od.write_bytes(c.index, 0, c.data, c.length), c.expected);
  if (c.expected == AbortCode::none) {
    EXPECT_EQ(*od.read_number(c.index, 0), c.stored);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Sdo, SdoLengthTable,
    ::testing::Values(
        SdoCase{0x2002, bytes({0x34, 0x12}), SdoLength::indicated, AbortCode::none, 0x1234},
        SdoCase{0x2002, bytes({0x34, 0x12, 0, 0}), SdoLength::indicated, AbortCode::length_too_high, 0},
        SdoCase{0x2002, bytes({0x34}), SdoLength::indicated, AbortCode::length_too_low, 0},
        SdoCase{0x2002, bytes({0x34, 0x12, 0xAA, 0xBB}), SdoLength::expedited_unindicated, AbortCode::none, 0x1234},
        SdoCase{0x2002, bytes({0x34, 0x12, 0}), SdoLength::segmented_unindicated, AbortCode::type_mismatch, 0},
        SdoCase{0x2002, bytes({0x34, 0x12}), SdoLength::segmented_unindicated, AbortCode::none, 0x1234},
        SdoCase{0x2003, bytes({0xFF, 0xFF}), SdoLength::indicated, AbortCode::none, -1},
        SdoCase{0x2005, bytes({0x00, 0x00, 0x00, 0x80}), SdoLength::indicated, AbortCode::none, -2147483648LL},
        SdoCase{0x2004, bytes({0xFF, 0xFF, 0xFF, 0xFF}), SdoLength::indicated, AbortCode::none, 4294967295LL},
        SdoCase{0x2001, bytes({0x80}), SdoLength::indicated, AbortCode::none, -128},
        SdoCase{0x2202, bytes({0xFF, 0xFF, 0, 0}), SdoLength::indicated, AbortCode::none, 65535},
        SdoCase{0x2202, bytes({0x00, 0x00, 1, 0}), SdoLength::indicated, AbortCode::value_too_high, 0},
        SdoCase{0x2202, bytes({0xFF, 0xFF, 0xFF, 0xFF}), SdoLength::indicated, AbortCode::value_too_low, 0},
        SdoCase{0x2202, bytes({1, 0, 0}), SdoLength::indicated, AbortCode::length_too_high, 0},
        SdoCase{0x2007, bytes({1, 0, 0, 0}), SdoLength::indicated, AbortCode::read_only, 0}));

TEST(Dictionary, CheckDownloadRunsChecksOneToFour) {
  ObjectDictionary od(test_entries());
  EXPECT_EQ(od.check_download(0x3000, 0, 2), AbortCode::no_object);
  EXPECT_EQ(od.check_download(0x2000, 9, 1), AbortCode::no_sub);
  EXPECT_EQ(od.check_download(0x2006, 0, 12), AbortCode::read_only);
  EXPECT_EQ(od.check_download(0x2002, 0, 4), AbortCode::length_too_high);
  EXPECT_EQ(od.check_download(0x2202, 0, 4), AbortCode::none);
  EXPECT_EQ(od.check_download(0x2004, 0, 2), AbortCode::length_too_low);
  EXPECT_EQ(od.check_download(0x2004, 0, std::nullopt), AbortCode::none);
}

TEST(Dictionary, ReadBytesAreLittleEndianOfTheTypeSize) {
  ObjectDictionary od(test_entries());
  ASSERT_EQ(od.write(0x2003, 0, std::int64_t{-2}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(*od.read_bytes(0x2003, 0), bytes({0xFE, 0xFF}));
  EXPECT_EQ(od.read_bytes(0x2006, 0)->size(), 12u);
}

TEST(Dictionary, HookRefusalChangesNothingAndHookMayReplaceValue) {
  ObjectDictionary od(test_entries());
  int calls = 0;
  od.on_write(0x2005, 0, [&](WriteRequest& r) {
    ++calls;
    const auto v = std::get<std::int64_t>(r.value);
    if (v == 13) return AbortCode::device_state;
    r.value = Value{v * 2};
    return AbortCode::none;
  });
  EXPECT_EQ(od.write(0x2005, 0, std::int64_t{13}, Origin::sdo), AbortCode::device_state);
  EXPECT_EQ(*od.read_number(0x2005, 0), 0);
  EXPECT_EQ(od.write(0x2005, 0, std::int64_t{4}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(*od.read_number(0x2005, 0), 8);
  EXPECT_EQ(od.write(0x2005, 0, std::int64_t{1LL << 40}, Origin::sdo), AbortCode::value_too_high);
  EXPECT_EQ(calls, 2) << "the hook runs only after the type and limit checks";
}

TEST(Dictionary, PendingWriteCompletesLater) {
  ObjectDictionary od(test_entries());
  Done parked;
  od.on_write(0x2004, 0, [&](WriteRequest& r) {
    parked = std::move(*r.done);
    return AbortCode::pending;
  });
  AbortCode result = AbortCode::general;
  EXPECT_EQ(od.write(0x2004, 0, std::int64_t{1}, Origin::refgo, [&](AbortCode c) { result = c; }), AbortCode::pending);
  ASSERT_TRUE(parked);
  parked(AbortCode::none);
  EXPECT_EQ(result, AbortCode::none);
}

TEST(Dictionary, ReentrantHookWritesOtherEntries) {
  ObjectDictionary od(test_entries());
  od.on_write(0x2000, 0, [&](WriteRequest& r) { return od.write(0x2007, 0, r.value, Origin::internal); });
  EXPECT_EQ(od.write(0x2000, 0, std::int64_t{42}, Origin::sdo), AbortCode::none);
  EXPECT_EQ(*od.read_number(0x2007, 0), 42);
}

TEST(Dictionary, ASecondHookOnAnEntryIsRefusedNotSwapped) {
  ObjectDictionary od(test_entries());
  od.on_write(0x2000, 0, [](WriteRequest&) { return AbortCode::invalid_value; });
  EXPECT_THROW(od.on_write(0x2000, 0, [](WriteRequest&) { return AbortCode::none; }), std::logic_error);
  EXPECT_EQ(od.write(0x2000, 0, Value{std::int64_t{1}}, Origin::sdo), AbortCode::invalid_value) << "first hook kept";
  od.on_write(0x2000, 0, {});  // removed by its owner, then a new one is fine
  od.on_write(0x2000, 0, [](WriteRequest&) { return AbortCode::none; });
  EXPECT_EQ(od.write(0x2000, 0, Value{std::int64_t{1}}, Origin::sdo), AbortCode::none);
  const ReadHook hook = [](const EntryInfo&) -> Result<Value> { return Value{std::int64_t{7}}; };
  od.on_read(0x2001, 0, hook);
  EXPECT_THROW(od.on_read(0x2001, 0, hook), std::logic_error);
}

TEST(Dictionary, ReadHookProducesValue) {
  ObjectDictionary od(test_entries());
  od.on_read(0x2007, 0, [](const EntryInfo&) -> Result<Value> { return Value{std::int64_t{99}}; });
  EXPECT_EQ(*od.read_number(0x2007, 0), 99);
  od.on_read(0x2000, 0, [](const EntryInfo&) -> Result<Value> { return AbortCode::no_data; });
  EXPECT_EQ(od.read(0x2000, 0).error(), AbortCode::general);
}

TEST(Dictionary, ChangeListenerSeesOnlyChanges) {
  ObjectDictionary od(test_entries());
  std::vector<std::pair<std::uint16_t, std::int64_t>> seen;
  od.on_change([&](const EntryInfo& i, const Value& v) { seen.emplace_back(i.index, std::get<std::int64_t>(v)); });
  od.write(0x2000, 0, std::int64_t{1}, Origin::sdo);
  od.write(0x2000, 0, std::int64_t{1}, Origin::sdo);
  od.write(0x2000, 0, std::int64_t{300}, Origin::sdo);
  od.set(od.handle(0x2007, 0), std::int64_t{8});
  const std::array<StoredValue, 1> load{StoredValue{0x2001, 0, std::int64_t{5}}};
  od.load_values(load);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], (std::pair<std::uint16_t, std::int64_t>{0x2000, 1}));
  EXPECT_EQ(seen[1], (std::pair<std::uint16_t, std::int64_t>{0x2007, 8}));
}

// A listener that names its entries is called for those alone; one that names none of the
// dictionary's entries is never called, and an unnamed listener still sees every change.
TEST(Dictionary, ChangeListenerForNamedEntries) {
  ObjectDictionary od(test_entries());
  std::vector<std::uint16_t> named, absent, all;
  od.on_change({{0x2000, 0}, {0x2100, 1}}, [&](const EntryInfo& i, const Value&) { named.push_back(i.index); });
  od.on_change({{0x7000, 0}}, [&](const EntryInfo& i, const Value&) { absent.push_back(i.index); });
  od.write(0x2000, 0, std::int64_t{1}, Origin::sdo);
  od.write(0x2001, 0, std::int64_t{2}, Origin::sdo);
  od.set(od.handle(0x2007, 0), std::int64_t{8});
  od.on_change([&](const EntryInfo& i, const Value&) { all.push_back(i.index); });
  od.write(0x2100, 1, std::int64_t{3}, Origin::sdo);
  od.write(0x2100, 3, std::int64_t{4}, Origin::sdo);
  EXPECT_EQ(named, (std::vector<std::uint16_t>{0x2000, 0x2100}));
  EXPECT_TRUE(absent.empty());
  EXPECT_EQ(all, (std::vector<std::uint16_t>{0x2100, 0x2100}));
}

// settings_generation() counts changes of the entries a master can write (rw, wo) and every bulk
// load; the drive's own values (ro) and unchanged writes leave it alone. generation() counts all.
TEST(Dictionary, SettingsGenerationCountsWritableEntriesOnly) {
  ObjectDictionary od(test_entries());
  const auto s0 = od.settings_generation();
  const auto g0 = od.generation();
  od.set(od.handle(0x2007, 0), std::int64_t{8});  // ro
  EXPECT_EQ(od.settings_generation(), s0);
  EXPECT_EQ(od.generation(), g0 + 1);
  od.write(0x2000, 0, std::int64_t{0}, Origin::sdo);  // unchanged
  EXPECT_EQ(od.settings_generation(), s0);
  od.write(0x2000, 0, std::int64_t{1}, Origin::sdo);  // rw
  EXPECT_EQ(od.settings_generation(), s0 + 1);
  od.write(0x2008, 0, std::int64_t{1}, Origin::sdo);  // wo
  EXPECT_EQ(od.settings_generation(), s0 + 2);
  const std::array<StoredValue, 1> load{StoredValue{0x2007, 0, std::int64_t{9}}};
  od.load_values(load);  // a bulk load of an ro entry still counts
  EXPECT_EQ(od.settings_generation(), s0 + 3);
  EXPECT_EQ(od.generation(), g0 + 4);
}

// SettingsCache computes once, keeps the value while no setting changes (the drive's own ro values
// move every step), and computes again after a setting write and after a bulk load.
TEST(Dictionary, SettingsCacheRecomputesOnlyAfterASettingChanged) {
  ObjectDictionary od(test_entries());
  SettingsCache<std::int64_t> cache;
  int computed = 0;
  const auto read = [&] {
    return cache.get(od, [&] {
      ++computed;
      return od.number(od.handle(0x2000, 0));
    });
  };
  EXPECT_EQ(read(), 0);
  EXPECT_EQ(read(), 0);
  EXPECT_EQ(computed, 1);
  od.set(od.handle(0x2007, 0), std::int64_t{8});  // ro: not a setting
  EXPECT_EQ(read(), 0);
  EXPECT_EQ(computed, 1);
  od.write(0x2000, 0, std::int64_t{5}, Origin::sdo);
  EXPECT_EQ(read(), 5);
  EXPECT_EQ(computed, 2);
  const std::array<StoredValue, 1> load{StoredValue{0x2000, 0, std::int64_t{7}}};
  od.load_values(load);
  EXPECT_EQ(read(), 7);
  EXPECT_EQ(computed, 3);
}

// set() takes a fast path for plain entries (a number without limits, validator or write hook):
// it must give exactly the results of the full path — type range, unsigned32 bit pattern, no change
// for an equal value — and stop being taken once a hook is registered, and again once it is removed.
TEST(Dictionary, SetOnPlainEntriesMatchesTheFullPath) {
  ObjectDictionary od(test_entries());
  const Handle u8 = od.handle(0x2000, 0);
  const Handle u32 = od.handle(0x2004, 0);
  EXPECT_EQ(od.set(u8, std::int64_t{256}), AbortCode::value_too_high);
  EXPECT_EQ(od.set(u8, std::int64_t{-1}), AbortCode::value_too_low);
  EXPECT_EQ(od.set(u32, std::int64_t{-1}), AbortCode::none);
  EXPECT_EQ(od.number(u32), 4294967295LL);
  EXPECT_EQ(std::get<std::int64_t>(od.value(u32)), 4294967295LL) << "entry and compact array agree";
  const auto before = od.generation();
  EXPECT_EQ(od.set(u32, std::int64_t{4294967295LL}), AbortCode::none);
  EXPECT_EQ(od.generation(), before) << "an equal value is no change";
  EXPECT_EQ(od.set(od.handle(0x2200, 0), std::int64_t{0}), AbortCode::value_too_low) << "limits: full path";
  EXPECT_EQ(od.set(od.handle(0x2201, 0), std::int64_t{2}), AbortCode::invalid_value) << "validator: full path";
  EXPECT_EQ(od.set(od.handle(0x2006, 0), std::int64_t{1}), AbortCode::type_mismatch) << "string entry";

  int calls = 0;
  od.on_write(0x2000, 0, [&](WriteRequest& req) {
    ++calls;
    req.value = Value{std::int64_t{42}};
    return AbortCode::none;
  });
  EXPECT_EQ(od.set(u8, std::int64_t{5}), AbortCode::none);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(od.number(u8), 42) << "the hook's value is stored";
  od.on_write(0x2000, 0, {});
  EXPECT_EQ(od.set(u8, std::int64_t{5}), AbortCode::none);
  EXPECT_EQ(calls, 1) << "removed hook is not called";
  EXPECT_EQ(od.number(u8), 5);
}

TEST(Dictionary, BulkLoadChecksTypeAndLimitsButNotAccessOrHooks) {
  ObjectDictionary od(test_entries());
  bool hooked = false;
  od.on_write(0x2005, 0, [&](WriteRequest&) {
    hooked = true;
    return AbortCode::none;
  });
  const std::vector<StoredValue> load{
      {0x2007, 0, std::int64_t{77}},  // ro: accepted by a bulk load
      {0x2005, 0, std::int64_t{-5}},  // hook not run
      {0x2200, 0, std::int64_t{0}},   // below limit: keeps its value
      {0x2000, 0, S("text")},         // wrong kind
      {0x2999, 0, std::int64_t{1}},   // unknown object
  };
  const auto issues = od.load_values(load);
  EXPECT_FALSE(hooked);
  EXPECT_EQ(*od.read_number(0x2007, 0), 77);
  EXPECT_EQ(*od.read_number(0x2005, 0), -5);
  EXPECT_EQ(*od.read_number(0x2200, 0), 5);
  ASSERT_EQ(issues.size(), 3u);
  EXPECT_EQ(issues[0].code, AbortCode::value_too_low);
  EXPECT_EQ(issues[1].code, AbortCode::type_mismatch);
  EXPECT_EQ(issues[2].code, AbortCode::no_object);
}

TEST(Dictionary, ForEachIsAscending) {
  ObjectDictionary od(test_entries());
  std::vector<std::pair<int, int>> keys;
  od.for_each([&](const EntryInfo& i, const Value&) { keys.emplace_back(i.index, i.sub); });
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  EXPECT_EQ(keys.size(), od.size());
}

TEST(Dictionary, DuplicateEntriesAreABuildError) {
  auto e = test_entries();
  e.push_back(entry(0x2000, 0, DataType::unsigned8, Access::rw));
  EXPECT_THROW(ObjectDictionary{e}, std::logic_error);
}

// The write tap (the master lint): every write() and write_bytes() with what was asked and the
// result — refused writes too; set() and load_values() are not taps; HelperScope marks writes.
TEST(Dictionary, WriteTapSeesEveryWriteWithItsResult) {
  ObjectDictionary od(test_entries());
  std::vector<WriteNote> seen;
  od.set_write_tap([&](const WriteNote& n) { seen.push_back(n); });
  const std::array<std::byte, 2> le{std::byte{0x34}, std::byte{0x12}};
  const std::array<std::byte, 4> wide{std::byte{0x10}, std::byte{0x00}, std::byte{0x00}, std::byte{0x00}};
  od.write(0x2004, 0, Value{std::int64_t{-1}}, Origin::refgo);                    // U32 pattern
  od.write(0x2007, 0, Value{std::int64_t{1}}, Origin::sdo);                       // read only: refused
  od.write(0x2300, 0, Value{std::int64_t{1}}, Origin::web);                       // no object
  od.write_bytes(0x2002, 0, le, SdoLength::indicated, Origin::sdo);               // decoded
  od.write_bytes(0x2202, 0, wide, SdoLength::indicated, Origin::sdo);             // length tolerant
  od.write(0x2006, 0, Value{std::string("x")}, Origin::internal);                 // a string: 0
  od.set(od.handle(0x2000, 0), Value{std::int64_t{5}});                           // not a tap
  od.load_values(std::vector<StoredValue>{{0x2000, 0, Value{std::int64_t{6}}}});  // not a tap
  {
    const ObjectDictionary::HelperScope helper(od);
    od.write(0x2005, 0, Value{std::int64_t{-7}}, Origin::script);
  }
  od.write(0x2005, 0, Value{std::int64_t{8}}, Origin::script);
  struct Expect {
    std::uint16_t index;
    std::int64_t value;
    Origin origin;
    AbortCode result;
    bool helper;
  };
  const std::vector<Expect> want = {
      {0x2004, 4294967295LL, Origin::refgo, AbortCode::none, false},
      {0x2007, 1, Origin::sdo, AbortCode::read_only, false},
      {0x2300, 1, Origin::web, AbortCode::no_object, false},
      {0x2002, 0x1234, Origin::sdo, AbortCode::none, false},
      {0x2202, 0x10, Origin::sdo, AbortCode::none, false},
      {0x2006, 0, Origin::internal, AbortCode::none, false},
      {0x2005, -7, Origin::script, AbortCode::none, true},
      {0x2005, 8, Origin::script, AbortCode::none, false},
  };
  ASSERT_EQ(seen.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(seen[i].index, want[i].index);
    EXPECT_EQ(seen[i].value, want[i].value);
    EXPECT_EQ(seen[i].origin, want[i].origin);
    EXPECT_EQ(seen[i].result, want[i].result);
    EXPECT_EQ(seen[i].helper, want[i].helper);
  }
  od.set_write_tap({});  // removed: nothing more is seen
  od.write(0x2000, 0, Value{std::int64_t{1}}, Origin::sdo);
  EXPECT_EQ(seen.size(), want.size());
}

TEST(AbortCodes, ErrorCategory) {
  std::error_code ec = AbortCode::no_object;
  EXPECT_EQ(ec.message(), "Object does not exist in the object dictionary");
  EXPECT_STREQ(ec.category().name(), "sdo-abort");
}

}  // namespace
}  // namespace mcemu::od
