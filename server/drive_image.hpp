// The server's side of a drive's factory image: the preset of a drive's Settings (--model and the
// "model_overrides" of its config; the mapping itself is the bundle's, device/config_image.hpp) and
// the EDS file information, whose date is today's (it reads the clock).
#pragma once

#include "device/config_image.hpp"
#include "drive/model/model_preset.hpp"
#include "protocols/canopen/eds.hpp"
#include "server/settings.hpp"

namespace mcemu::server {

using device::apply_config_objects;
using device::dump_od;

// The preset named by --model with "model_overrides" of the config applied; throws UsageError.
model::ModelPreset make_preset(const Settings& settings);
// The file information of the EDS (--dump-eds, GET /api/v1/eds); the date is today's (CiA 306 formats).
canopen::EdsInfo eds_info(const model::ModelPreset& preset);

}  // namespace mcemu::server
