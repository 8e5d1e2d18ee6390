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
  // The vendor is the preset's (Fullmo for a MovingCap, FAULHABER for an FH_ model); VendorNumber,
  // ProductName and ProductNumber come from the dictionary (1018h, 1008h), which the preset fills.
  info.vendor_name = preset.identity.vendor_name;
  info.description = preset.family == model::Family::faulhaber
                         ? preset.identity.display_name + " (" + preset.name + ") emulated by mcemu"
                         : "MovingCap " + preset.name + " (" + preset.identity.device_name + ") emulated by mcemu";
  info.date = date;
  info.time = time;
  return info;
}

}  // namespace mcemu::server
