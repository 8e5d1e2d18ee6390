// The factory image of the emulated drive (persistence.md §5): XDD → model preset →
// "model_overrides"/"objects" of --config; and the --dump-od document. Throws UsageError
// with a one-line message for any invalid config value.
#pragma once

#include <nlohmann/json.hpp>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/canopen/eds.hpp"
#include "server/settings.hpp"

namespace mcemu::server {

// The preset named by --model with "model_overrides" of the config applied ("plant" and "homing"
// are the drive core's: server/plant_settings.hpp).
model::ModelPreset make_preset(const Settings& settings);
// Installs the "objects" section ({"IIII.SS": value}) as part of the factory image (bulk load).
void apply_config_objects(od::ObjectDictionary& od, const nlohmann::json& config);
// The file information of the EDS (--dump-eds, GET /api/v1/eds); the date is today's (CiA 306 formats).
canopen::EdsInfo eds_info(const model::ModelPreset& preset);
// object-dictionary.md §8.5
nlohmann::json dump_od(const od::ObjectDictionary& od, const std::string& model);

}  // namespace mcemu::server
