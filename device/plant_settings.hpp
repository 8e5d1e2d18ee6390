// Maps the "plant" and "homing" sections of --config to the drive core's PlantConfig
// (drive/plant_config.hpp lists the keys; models.md §4, drive-core.md §9.4, §10.2).
// Throws ConfigError with one line naming the key for an unknown key or a value of the wrong type.
#pragma once

#include <nlohmann/json.hpp>

#include "drive/plant_config.hpp"

namespace mcemu::device {

core::PlantConfig plant_config_from_json(const nlohmann::json& config);

}  // namespace mcemu::device
