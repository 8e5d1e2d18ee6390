// Maps the "plant" and "homing" sections of --config to the drive core's PlantConfig (models.md §4,
// drive-core.md §9.4, §10.2): the one place that knows their keys (the table in plant_settings.cpp;
// "noise" {enabled, inc, seed} and "regen" {enabled, capacitance_F} are objects of their own).
// Throws ConfigError with one line naming the key for an unknown key or a value of the wrong type.
#pragma once

#include <nlohmann/json.hpp>

#include "drive/plant_config.hpp"

namespace mcemu::device {

core::PlantConfig plant_config_from_json(const nlohmann::json& config);

}  // namespace mcemu::device
