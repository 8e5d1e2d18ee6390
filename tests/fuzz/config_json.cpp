// Fuzz target: the --config JSON document as mcemu's start-up reads it (spec README "Command line",
// persistence.md §5): JSON parse, the flags and per-service sections (server/settings.cpp), then the
// drive bundle built on it as the server builds it (tests/support/device_fixture.hpp,
// device/device.hpp): the preset with "model_overrides", the dictionary with "objects", "plant" and
// "homing", "slcan", "canopen" and "settings", the core powered on.
// Oracles: a bad document ends in the one documented error (UsageError or std::invalid_argument,
// which main turns into one line and exit status 2) — any other exception escapes and is a finding;
// an accepted document never corrupts the dictionary, and the drive powers on and steps.
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "server/settings.hpp"
#include "tests/fuzz/drive_bundle.hpp"
#include "tests/support/device_fixture.hpp"

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
    mcemu::testing::DeviceOptions options;
    options.config = s.config;
    options.keep_events = false;
    mcemu::testing::DeviceFixture drive(s.model, std::move(options));
    drive.step(10);
    fuzz::check_dictionary(drive.od());
  } catch (const server::UsageError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
