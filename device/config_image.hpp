// The factory image of the emulated drive (persistence.md §5): XDD → model preset →
// "model_overrides"/"objects" of --config; and the --dump-od document. Throws ConfigError
// with a one-line message for any invalid config value.
#pragma once

#include <nlohmann/json.hpp>

#include "device/config_error.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"

namespace mcemu::device {

// The preset named by --model with "model_overrides" of the config applied ("plant" and "homing"
// are the drive core's: device/plant_settings.hpp).
model::ModelPreset make_preset(const std::string& model, const nlohmann::json& config);
// Installs the "objects" section ({"IIII.SS": value}) as part of the factory image (bulk load).
void apply_config_objects(od::ObjectDictionary& od, const nlohmann::json& config);
// object-dictionary.md §8.5
nlohmann::json dump_od(const od::ObjectDictionary& od, const std::string& model);

}  // namespace mcemu::device
