// The "plant" and "homing" sections of --config mapped onto the drive core's PlantConfig
// (drive-core.md §10.2, models.md §4).
#include "server/plant_settings.hpp"

#include <gtest/gtest.h>

#include "drive/model/model_preset.hpp"
#include "server/settings.hpp"

namespace mcemu::server {
namespace {

using json = nlohmann::json;

core::PlantParams resolve(const std::string& model, const json& config) {
  return core::resolve_plant(*model::find_preset(model), plant_config_from_json(config));
}

TEST(PlantSettings, DefaultsAreThePresetsValues) {
  const auto p = resolve("MCFLAT", json::object());
  ASSERT_TRUE(p.stops_inc);
  EXPECT_EQ(p.stops_inc->second, 200000);
  EXPECT_EQ(p.power_on_position_inc, 100000);
  EXPECT_DOUBLE_EQ(p.p_idle_w, 2);
}

TEST(PlantSettings, EveryKindOfKey) {
  const auto p = resolve("MCFLAT", json{{"plant",
                                         {{"stroke_mm", 400},
                                          {"coulomb", 3.5},
                                          {"P_idle", 4},
                                          {"uv_V", 20},
                                          {"following_error_limit", 1234},
                                          {"hw_enable_fitted", true},
                                          {"noise", {{"enabled", true}, {"inc", 3}, {"seed", 9}}},
                                          {"regen", {{"enabled", true}, {"capacitance_F", 0.002}}},
                                          {"position_switches", {{{"input", 5}, {"from_inc", 0}, {"to_inc", 10}}}}}},
                                        {"homing", {{"max_search_ms", 1000}, {"enable_method_18", true}}}});
  ASSERT_TRUE(p.stops_inc);
  EXPECT_EQ(p.stops_inc->second, 400000) << "stroke_mm sets the stops";
  EXPECT_EQ(p.power_on_position_inc, 200000) << "and the middle of the stroke";
  EXPECT_DOUBLE_EQ(p.p_idle_w, 4);
  EXPECT_DOUBLE_EQ(p.supply_uv_v, 20);
  EXPECT_EQ(p.following_error_limit_inc, 1234);
  EXPECT_TRUE(p.hw_enable_fitted);
  EXPECT_TRUE(p.noise.enabled);
  EXPECT_EQ(p.noise.inc, 3);
  EXPECT_EQ(p.noise.seed, 9u);
  EXPECT_TRUE(p.regen.enabled);
  const auto c = plant_config_from_json(json{{"homing", {{"max_search_ms", 1000}, {"enable_method_18", true}}}});
  EXPECT_EQ(c.homing.max_search_ms, 1000);
  EXPECT_TRUE(c.homing.enable_method_18);
}

TEST(PlantSettings, InvalidValuesAreUsageErrors) {
  for (const json& bad :
       {json{{"plant", {{"colour", 1}}}}, json{{"plant", {{"coulomb", "high"}}}}, json{{"plant", {{"stops", {1}}}}},
        json{{"plant", {{"noise", {{"loud", true}}}}}}, json{{"plant", 5}}, json{{"homing", {{"max_search_ms", 1.5}}}},
        json{{"homing", {{"method", 19}}}}}) {
    EXPECT_THROW(plant_config_from_json(bad), UsageError) << bad.dump();
  }
}

TEST(PlantSettings, ModelRulesAreCheckedWhenResolving) {
  EXPECT_THROW(resolve("MC349", json{{"plant", {{"stroke_mm", 100}}}}), std::invalid_argument)
      << "stroke only on linear models";
  EXPECT_THROW(resolve("MC349", json{{"plant", {{"hw_enable_fitted", true}}}}), std::invalid_argument)
      << "HW enable is a power pin on MC349 (models.md §5)";
  EXPECT_THROW(resolve("MC349", json{{"plant", {{"stops", {5, 1}}}}}), std::invalid_argument);
  EXPECT_THROW(
      resolve("MC349", json{{"plant", {{"position_switches", {{{"input", 6}, {"from_inc", 0}, {"to_inc", 1}}}}}}}),
      std::invalid_argument)
      << "MC349 has no IN6 pin";
}

}  // namespace
}  // namespace mcemu::server
