// The stored image and its file format (persistence.md §2, §9, §11).
#include "persistence/state_document.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>

#include "drive/model/model_preset.hpp"

namespace mcemu::persistence {
namespace {

od::ObjectDictionary make(std::string_view model) { return od::ObjectDictionary(*model::find_preset(model)); }

TEST(Groups, FollowTheSpec) {
  auto od = make("MCFLAT");
  const auto g = [&](std::uint16_t i, std::uint8_t s) { return group_of(*od.info(i, s)); };
  EXPECT_EQ(g(0x6083, 0), Group::parameters);
  EXPECT_EQ(g(0x1017, 0), Group::parameters) << "comm entries are stored with the parameters";
  EXPECT_EQ(g(0x3300, 7), Group::motor);
  EXPECT_EQ(g(0x3301, 4), Group::parameters);
  EXPECT_EQ(g(0x3404, 3), Group::network);
  EXPECT_EQ(g(0x5007, 1), Group::network);
  EXPECT_EQ(g(0x5008, 4), Group::network);
  EXPECT_EQ(g(0x5006, 5), Group::nvm);
  EXPECT_EQ(g(0x3500, 4), Group::parameters);
  for (auto [i, s] : std::initializer_list<std::pair<std::uint16_t, std::uint8_t>>{{0x6040, 0},
                                                                                   {0x6060, 0},
                                                                                   {0x607A, 0},
                                                                                   {0x60FF, 0},
                                                                                   {0x60FE, 1},
                                                                                   {0x3510, 1},
                                                                                   {0x3510, 2},
                                                                                   {0x1010, 1},
                                                                                   {0x1011, 1},
                                                                                   {0x3010, 1},
                                                                                   {0x1003, 0},
                                                                                   {0x1F51, 1},
                                                                                   {0x3500, 2},
                                                                                   {0x3401, 0x19},
                                                                                   {0x6041, 0},
                                                                                   {0x1000, 0}}) {
    EXPECT_EQ(g(i, s), Group::none) << std::hex << i << "." << int(s) << " is volatile";
  }
  auto n23 = make("MCN23");
  EXPECT_EQ(group_of(*n23.info(0x2000, 1)), Group::none);
  EXPECT_EQ(group_of(*n23.info(0x2000, 3)), Group::none);
  EXPECT_EQ(group_of(*n23.info(0x5002, 1)), Group::none);
  EXPECT_EQ(group_of(*n23.info(0x5001, 2)), Group::none);
}

TEST(Keys, FormatAndParse) {
  EXPECT_EQ(object_key(0x6083, 0), "6083.00");
  EXPECT_EQ(object_key(0x351A, 0x0A), "351A.0A");
  EXPECT_EQ(parse_object_key("351A.0A"), (std::pair<std::uint16_t, std::uint8_t>{0x351A, 0x0A}));
  EXPECT_FALSE(parse_object_key("6083.0"));
  EXPECT_FALSE(parse_object_key("6083-00"));
  EXPECT_FALSE(parse_object_key("60G3.00"));
}

TEST(Crc32, KnownValues) {
  EXPECT_EQ(crc32("123456789"), 0xCBF43926U);
  EXPECT_EQ(crc32("#id (empty)\r\n"), 0x23883CEFU) << "the placeholder script's CRC (persistence.md §4)";
  EXPECT_EQ(hex32(0x8a41c0de), "0x8a41c0de");
}

TEST(Document, RoundTripIsExactAndCanonical) {
  auto od = make("MC349");
  ASSERT_EQ(od.write(0x6083, 0, od::Value{std::int64_t{2000}}, od::Origin::sdo), od::AbortCode::none);
  ASSERT_EQ(od.write(0x340F, 1, od::Value{std::int64_t{-1}}, od::Origin::script), od::AbortCode::none);
  Image img = snapshot(od);
  img.home_offset_inc = -123;
  img.autostart = true;
  img.script = {{"id", "x.py"}, {"encoding", "utf-8"}, {"source", "#id x.py\nprint(1)\n"}, {"crc32", "0x1"}};
  const std::string text = serialize(img, "MC349", "0.1.0", "2026-01-15T10:15:02Z");
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_NE(text.find("\n  \"format\": \"mcemu-drive-state\""), std::string::npos) << "2-space indent";
  auto parsed = parse(text, "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParsedFile>(parsed));
  const auto& p = std::get<ParsedFile>(parsed);
  EXPECT_TRUE(p.bad_keys.empty());
  EXPECT_EQ(serialize(p.image, "MC349", "0.1.0", "x"), serialize(img, "MC349", "0.1.0", "x")) << "the same image";
  EXPECT_EQ(p.image.home_offset_inc, -123);
  EXPECT_TRUE(p.image.autostart);
  // 340Fh.01 is UNSIGNED32: stored as its bit pattern
  EXPECT_NE(text.find("\"340F.01\": 4294967295"), std::string::npos);
}

struct Corrupt {
  const char* name;
  std::string text;
  std::string reason;
};

class CorruptFiles : public ::testing::TestWithParam<Corrupt> {};

TEST_P(CorruptFiles, AreRejectedWithAReason) {
  auto od = make("MC349");
  auto r = parse(GetParam().text, "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParseFailure>(r));
  EXPECT_NE(std::get<ParseFailure>(r).reason.find(GetParam().reason), std::string::npos)
      << std::get<ParseFailure>(r).reason;
}

std::string valid_text(std::string_view model = "MC349") {
  auto od = make(model);
  return serialize(snapshot(od), model, "0.1.0", "x");
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CorruptFiles,
    ::testing::Values(Corrupt{"truncated", valid_text().substr(0, 300), "not valid JSON"},
                      Corrupt{"random", std::string("\x89PNG\r\n\x1a\n\x00\x01", 10), "not valid JSON"},
                      Corrupt{"array", "[1,2,3]", "not a JSON object"},
                      Corrupt{"crc", replace(valid_text(), "\"6083.00\": 1000", "\"6083.00\": 1001"), "payload_crc32"},
                      Corrupt{"format", replace(valid_text(), "mcemu-drive-state", "other"), "wrong format"},
                      Corrupt{"newer", replace(valid_text(), "\"format_version\": 1", "\"format_version\": 2"),
                              "newer than supported"},
                      Corrupt{"missing", replace(valid_text(), "\"payload_crc32\"", "\"x\""), "missing member"},
                      Corrupt{"model", valid_text("MC349_AE"), "stored for model MC349_AE, running as MC349"}),
    [](const auto& p) { return std::string(p.param.name); });

// The file as the document used to write it (nlohmann-json: an object per level, dump(2)); the
// reference serialize() must equal byte for byte, since payload_crc32 and every file already on disk
// were made this way.
std::string serialize_as_document(const Image& image, std::string_view model, std::string_view version,
                                  std::string_view written) {
  using nlohmann::json;
  json objects = json::object();
  for (const auto& sv : image.objects) {
    const auto key = object_key(sv.index, sv.sub);
    if (std::holds_alternative<std::int64_t>(sv.value)) {
      objects[key] = std::get<std::int64_t>(sv.value);
    } else {
      objects[key] = std::get<std::string>(sv.value);
    }
  }
  const json payload{{"objects", objects},
                     {"home_offset_inc", image.home_offset_inc},
                     {"program", json{{"autostart", image.autostart}, {"script", image.script}}}};
  const json doc{{"format", k_format},
                 {"format_version", k_format_version},
                 {"model", model},
                 {"mcemu_version", version},
                 {"written_utc", written},
                 {"payload", payload},
                 {"payload_crc32", hex32(crc32(payload.dump()))}};
  return doc.dump(2) + "\n";
}

// Random text: plain ASCII, the characters JSON escapes, every control character, UTF-8 of one to
// four bytes, and (when `broken`) bytes that are not UTF-8: lone continuation bytes, overlong forms,
// surrogates, code points above U+10FFFF, sequences cut short.
std::string random_text(std::mt19937_64& rng, bool broken) {
  static const std::vector<std::string> pieces{"a",
                                               "Z",
                                               " ",
                                               "\"",
                                               "\\",
                                               "/",
                                               "\b",
                                               "\f",
                                               "\n",
                                               "\r",
                                               "\t",
                                               std::string(1, '\0'),
                                               "\x01",
                                               "\x1f",
                                               "\x7f",
                                               "\xc2\x80",
                                               "\xc3\xa9",
                                               "\xdf\xbf",
                                               "\xe0\xa0\x80",
                                               "\xe2\x82\xac",
                                               "\xed\x9f\xbf",
                                               "\xee\x80\x80",
                                               "\xef\xbf\xbf",
                                               "\xf0\x90\x80\x80",
                                               "\xf4\x8f\xbf\xbf",
                                               "{}",
                                               "[1,2]",
                                               "0x1F",
                                               "\u00e9"};
  static const std::vector<std::string> bad{"\x80",
                                            "\xbf",
                                            "\xc0\x80",
                                            "\xc1\xbf",
                                            "\xc2",
                                            "\xe0\x80\x80",
                                            "\xe0\x9f\xbf",
                                            "\xed\xa0\x80",
                                            "\xed\xbf\xbf",
                                            "\xe2\x82",
                                            "\xf0\x80\x80\x80",
                                            "\xf0\x8f\xbf\xbf",
                                            "\xf4\x90\x80\x80",
                                            "\xf5\x80\x80\x80",
                                            "\xff",
                                            "\xfe",
                                            "\xf0\x90\x80"};
  std::string s;
  const auto n = rng() % 12;
  for (std::uint64_t i = 0; i < n; ++i) {
    if (rng() % 50 == 0) {
      s.push_back(static_cast<char>(rng()));  // any byte
    } else {
      s += pieces[rng() % pieces.size()];
    }
  }
  if (broken) s.insert(rng() % (s.size() + 1), bad[rng() % bad.size()]);
  return s;
}

nlohmann::json random_script(std::mt19937_64& rng, int depth) {
  using nlohmann::json;
  switch (rng() % (depth > 3 ? 5 : 7)) {
    case 0: return nullptr;
    case 1: return static_cast<std::int64_t>(rng());
    case 2: return (rng() & 1) != 0;
    case 3: return random_text(rng, false);
    case 4: return static_cast<double>(static_cast<std::int64_t>(rng() % 2000000) - 1000000) / 64.0;
    case 5: {
      json a = json::array();
      for (std::uint64_t i = rng() % 4; i > 0; --i) a.push_back(random_script(rng, depth + 1));
      return a;
    }
    default: {
      json o = json::object();
      for (std::uint64_t i = rng() % 5; i > 0; --i) o[random_text(rng, false)] = random_script(rng, depth + 1);
      return o;
    }
  }
}

TEST(Document, SerializeWritesWhatTheDocumentWrote) {
  std::mt19937_64 rng(26);
  const std::array<std::int64_t, 8> edges{0, 1, -1, INT64_MIN, INT64_MAX, 4294967295LL, -2147483648LL, 255};
  int threw = 0;
  for (int round = 0; round < 3000; ++round) {
    Image img;
    const auto n = round % 10 == 0 ? 0 : rng() % 40;
    for (std::uint64_t i = 0; i < n; ++i) {
      // few indexes, so that keys repeat (the last one counts) and arrive out of order
      const auto index = static_cast<std::uint16_t>(rng() % 4 == 0 ? rng() : 0x6080 + rng() % 4);
      const auto sub = static_cast<std::uint8_t>(rng() % 3 == 0 ? rng() : rng() % 3);
      od::Value v;
      if (rng() % 4 == 0) {
        v = random_text(rng, round % 20 == 0 && i == 0);
      } else {
        v = rng() % 3 == 0 ? edges[rng() % edges.size()] : static_cast<std::int64_t>(rng() % 200001) - 100000;
      }
      img.objects.push_back({index, sub, v});
    }
    img.home_offset_inc = rng() % 2 == 0 ? edges[rng() % edges.size()] : static_cast<std::int64_t>(rng());
    img.autostart = (rng() & 1) != 0;
    img.script = rng() % 3 == 0 ? nlohmann::json(nullptr) : random_script(rng, 0);
    const std::string model = round % 7 == 0 ? random_text(rng, round % 14 == 0) : "MC349";
    const std::string version = round % 5 == 0 ? random_text(rng, false) : "0.3.0";
    const std::string written = round % 3 == 0 ? random_text(rng, false) : "2026-12-08T01:00:00Z";

    std::optional<std::string> want;
    std::optional<std::string> got;
    try {
      want = serialize_as_document(img, model, version, written);
    } catch (const nlohmann::json::type_error&) {
    }
    try {
      got = serialize(img, model, version, written);
    } catch (const nlohmann::json::type_error&) {
    }
    ASSERT_EQ(got, want) << "round " << round;
    if (!want) ++threw;
  }
  EXPECT_GT(threw, 100) << "text that is not UTF-8 was tried (and refused by both)";
}

TEST(Document, UnknownKeysAndBadValuesAreReportedNotFatal) {
  auto od = make("MC349");
  Image img = snapshot(od);
  img.objects.push_back({0x7000, 0, od::Value{std::int64_t{1}}});      // no such object
  img.objects.push_back({0x6040, 0, od::Value{std::int64_t{15}}});     // volatile: not storable
  img.objects.push_back({0x6083, 0, od::Value{std::string("fast")}});  // wrong type
  img.objects.push_back({0x340F, 2, od::Value{std::int64_t{-5}}});     // negative for U32
  const auto text = serialize(img, "MC349", "0.1.0", "x");
  auto r = parse(text, "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParsedFile>(r));
  const auto& p = std::get<ParsedFile>(r);
  EXPECT_EQ(p.bad_keys.size(), 4u);
  EXPECT_EQ(p.image.objects.size(), snapshot(od).objects.size() - 2) << "6083 and 340F.02 were replaced";
}

TEST(PlantFile, RoundTripAndModelCheck) {
  const auto t = serialize_plant("MC349_AE", -40000);
  EXPECT_EQ(parse_plant(t, "MC349_AE"), -40000);
  EXPECT_EQ(parse_plant(t, "MC349"), std::nullopt);
  EXPECT_EQ(parse_plant("{", "MC349_AE"), std::nullopt);
}

}  // namespace
}  // namespace mcemu::persistence

namespace mcemu::persistence {
namespace {

// Hardening (issue 12): a file beyond the size or object-count limit is rejected as corrupt, before
// (size) or instead of (count) being checked entry by entry.
TEST(Document, LimitsOfSizeAndObjectCount) {
  auto od = make("MC349");
  std::string big = valid_text();
  big.insert(big.size() - 2, std::string(k_max_state_file_bytes, ' '));  // whitespace: still valid JSON
  auto r = parse(big, "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParseFailure>(r));
  EXPECT_EQ(std::get<ParseFailure>(r).reason, "larger than 16 MiB");

  const auto with_objects = [](std::size_t n) {
    nlohmann::json objects = nlohmann::json::object();
    for (std::size_t i = 0; i < n; ++i) objects[std::to_string(i)] = 0;  // bad keys: not fatal one by one
    const nlohmann::json payload{{"objects", objects}};
    std::array<char, 16> crc{};
    std::snprintf(crc.data(), crc.size(), "0x%08x", crc32(payload.dump()));
    return nlohmann::json{{"format", "mcemu-drive-state"},
                          {"format_version", 1},
                          {"model", "MC349"},
                          {"payload", payload},
                          {"payload_crc32", crc.data()}}
        .dump();
  };
  auto many = parse(with_objects(k_max_state_objects + 1), "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParseFailure>(many));
  EXPECT_EQ(std::get<ParseFailure>(many).reason, "more than 65536 objects");
  auto at_limit = parse(with_objects(k_max_state_objects), "MC349", od);
  ASSERT_TRUE(std::holds_alternative<ParsedFile>(at_limit));
  EXPECT_EQ(std::get<ParsedFile>(at_limit).bad_keys.size(), k_max_state_objects);
}

}  // namespace
}  // namespace mcemu::persistence
