// Factory image from the preset and --config (persistence.md §5, models.md §3/§4, OD §8.5).
#include "server/drive_image.hpp"

#include <gtest/gtest.h>

namespace mcemu::server {
namespace {

using json = nlohmann::json;

Settings with_config(const std::string& model, json config) {
  Settings s;
  s.model = model;
  s.config = std::move(config);
  return s;
}

TEST(Preset, ModelOverrides) {
  const auto p = make_preset(
      with_config("MCFLAT", json{{"model_overrides", {{"serial", 7}, {"software_version", "v53.02.10.09_RABBIT"}}}}));
  EXPECT_EQ(p.identity.serial, 7u);
  EXPECT_EQ(p.identity.software_version, "v53.02.10.09_RABBIT");
  od::ObjectDictionary od(p);
  EXPECT_EQ(*od.read_number(0x3404, 4), 7);
  EXPECT_EQ(*od.read_number(0x1018, 4), 7);
  EXPECT_EQ(std::get<std::string>(*od.read(0x100A, 0)), "v53.02.10.09_RABBIT");
}

TEST(Preset, InvalidOverridesAreUsageErrors) {
  EXPECT_THROW(make_preset(with_config("MC349", json{{"model_overrides", {{"colour", "red"}}}})), UsageError);
  EXPECT_THROW(make_preset(with_config("MC349", json{{"model_overrides", {{"serial", -1}}}})), UsageError);
  EXPECT_THROW(make_preset(with_config("MC349", json{{"model_overrides", {{"device_name", 5}}}})), UsageError);
}

TEST(ConfigObjects, BecomePartOfTheFactoryImage) {
  od::ObjectDictionary od(*model::find_preset("MC349"));
  apply_config_objects(od, json{{"objects", {{"6083.00", 2000}, {"3404.03", 12}, {"1017.00", 100}}}});
  EXPECT_EQ(*od.read_number(0x6083, 0), 2000);
  EXPECT_EQ(*od.read_number(0x3404, 3), 12);
  for (const json& bad : {json{{"objects", {{"7000.00", 1}}}}, json{{"objects", {{"6083", 1}}}},
                          json{{"objects", {{"6083.00", 0}}}}, json{{"objects", {{"6060.00", 2}}}},
                          json{{"objects", {{"6083.00", "x"}}}}, json{{"objects", {{"6083.00", 1.5}}}}}) {
    EXPECT_THROW(apply_config_objects(od, bad), UsageError) << bad.dump();
  }
}

TEST(DumpOd, OneElementPerEntryAscending) {
  od::ObjectDictionary od(*model::find_preset("MC349"));
  const auto d = dump_od(od, "MC349");
  EXPECT_EQ(d["model"], "MC349");
  ASSERT_EQ(d["entries"].size(), od.size());
  const auto& first = d["entries"][0];
  EXPECT_EQ(first["index"], 0x1000);
  EXPECT_EQ(first["sub"], 0);
  EXPECT_EQ(first["name"], "Device Type");
  EXPECT_EQ(first["type"], "UNSIGNED32");
  EXPECT_EQ(first["access"], "ro");
  EXPECT_EQ(first["pdo"], "no");
  EXPECT_EQ(first["class"], "const");
  EXPECT_EQ(first["value"], 0x20192);
  EXPECT_FALSE(first.contains("min")) << "no range, no limits";
  int found = 0;
  for (const auto& e : d["entries"]) {
    if (e["index"] == 0x1008) {
      EXPECT_EQ(e["value"], "MC349_ETH_RE");
      ++found;
    }
    if (e["index"] == 0x3404 && e["sub"] == 3) {  // node-id 1 … 127 (object-dictionary.md §5)
      EXPECT_EQ(e["min"], 1);
      EXPECT_EQ(e["max"], 127);
      ++found;
    }
  }
  EXPECT_EQ(found, 2);
}

}  // namespace
}  // namespace mcemu::server
