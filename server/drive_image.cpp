#include "server/drive_image.hpp"

#include <ctime>

namespace mcemu::server {

model::ModelPreset make_preset(const Settings& settings) {
  return device::make_preset(settings.model, settings.config);
}

canopen::EdsInfo eds_info(const model::ModelPreset& preset) {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char date[16];
  char time[16];
  std::strftime(date, sizeof date, "%m-%d-%Y", &tm);
  std::strftime(time, sizeof time, "%I:%M%p", &tm);
  canopen::EdsInfo info;
  info.file_name = preset.name + ".eds";
  info.vendor_name = "Fullmo GmbH";
  info.description = "MovingCap " + preset.name + " (" + preset.identity.device_name + ") emulated by mcemu";
  info.date = date;
  info.time = time;
  return info;
}

}  // namespace mcemu::server
