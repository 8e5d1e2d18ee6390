// Fuzz target: the --config JSON document as mcemu's start-up reads it (spec README "Command line",
// persistence.md §5): JSON parse, the flags and per-service sections (server/settings.cpp), the
// preset with "model_overrides", the dictionary with "objects" (server/drive_image.cpp), "plant"
// and "homing" (server/plant_settings.cpp), "slcan" and "canopen", then the drive core built on it.
// Oracles: a bad document ends in the one documented error (UsageError or std::invalid_argument,
// which main turns into one line and exit status 2) — any other exception escapes and is a finding;
// an accepted document never corrupts the dictionary, and the core powers on and steps.
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "drive/drive_core.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/slcan/config.hpp"
#include "server/drive_image.hpp"
#include "server/plant_settings.hpp"
#include "server/settings.hpp"
#include "tests/fuzz/drive_bundle.hpp"

using namespace mcemu;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto doc = nlohmann::json::parse(data, data + size, nullptr, false);
  if (doc.is_discarded()) return 0;
  try {
    server::Settings s;
    server::apply_config(s, doc, {});
    (void)slcan::slcan_config_from_json(s.config.value("slcan", nlohmann::json::object()));
    (void)canopen::canopen_config_from_json(s.config.value("canopen", nlohmann::json::object()));
    const auto preset = server::make_preset(s);
    od::ObjectDictionary od(preset);
    server::apply_config_objects(od, s.config);
    const auto plant = server::plant_config_from_json(s.config);
    core::DriveCore core(preset, od, plant);
    core.power_on();
    core.step(10);
    fuzz::check_dictionary(od);
  } catch (const server::UsageError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
