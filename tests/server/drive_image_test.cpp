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

// --dump-eds and GET /api/v1/eds (both eds_info + make_eds): the [FileInfo] and [DeviceInfo] of the
// drive's own vendor and product — the preset's identity, never Fullmo's for a FAULHABER model.
struct EdsCase {
  const char* model;
  const char* description;
  const char* vendor_name;
  const char* vendor_number;
  const char* product_name;
  const char* product_number;
};

class EdsIdentity : public ::testing::TestWithParam<EdsCase> {};

TEST_P(EdsIdentity, FromThePreset) {
  const auto& c = GetParam();
  const auto preset = make_preset(with_config(c.model, json::object()));
  od::ObjectDictionary od(preset);
  const std::string eds = canopen::make_eds(od, eds_info(preset));
  const auto has = [&](const std::string& line) { return eds.find("\n" + line + "\n") != std::string::npos; };
  EXPECT_TRUE(has("FileName=" + std::string(c.model) + ".eds")) << eds.substr(0, 400);
  EXPECT_TRUE(has(std::string("Description=") + c.description)) << eds.substr(0, 400);
  EXPECT_TRUE(has(std::string("VendorName=") + c.vendor_name)) << eds.substr(0, 800);
  EXPECT_TRUE(has(std::string("VendorNumber=") + c.vendor_number)) << eds.substr(0, 800);
  EXPECT_TRUE(has(std::string("ProductName=") + c.product_name)) << eds.substr(0, 800);
  EXPECT_TRUE(has(std::string("ProductNumber=") + c.product_number)) << eds.substr(0, 800);
  const bool faulhaber = std::string(c.model).rfind("FH_", 0) == 0;
  EXPECT_EQ(eds.find("Fullmo") == std::string::npos, faulhaber) << "a FAULHABER EDS names no Fullmo";
  EXPECT_EQ(eds.find("MovingCap") == std::string::npos, faulhaber);
}

INSTANTIATE_TEST_SUITE_P(
    Models, EdsIdentity,
    ::testing::Values(EdsCase{"MC349", "MovingCap MC349 (MC349_ETH_RE) emulated by mcemu", "Fullmo GmbH", "0x0000053B",
                              "MC349_ETH_RE", "0x00000032"},
                      EdsCase{"FH_MC5005", "FAULHABER MC 5005 (FH_MC5005) emulated by mcemu",
                              "Dr. Fritz Faulhaber GmbH & Co. KG", "0x00000147", "MC 5005", "0x00000000"},
                      EdsCase{"FH_MCS", "FAULHABER MCS 3242 BX4 ET (FH_MCS) emulated by mcemu",
                              "Dr. Fritz Faulhaber GmbH & Co. KG", "0x00000147", "MCS 3242 BX4 ET", "0x00002D51"}),
    [](const auto& p) { return std::string(p.param.model); });

}  // namespace
}  // namespace mcemu::server
