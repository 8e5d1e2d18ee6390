// The "plant" and "homing" sections of --config as the server sees them: the mapping is the
// bundle's (device/plant_settings.hpp); UsageError is device::ConfigError.
#pragma once

#include "device/plant_settings.hpp"

namespace mcemu::server {

using device::plant_config_from_json;

}  // namespace mcemu::server
