#include "server/app.hpp"

#include <spdlog/spdlog.h>

#include "server/clock_driver.hpp"
#include "server/fleet.hpp"

namespace mcemu::server {

App::App(boost::asio::io_context& io, const Settings& settings) : io_(io), mode_(settings.clock) {
  const auto drives = expand_fleet(settings);
  const bool fleet = drives.size() > 1;
  units_.reserve(drives.size());
  for (std::size_t i = 0; i < drives.size(); ++i) {
    const int number = static_cast<int>(i) + 1;
    const std::string prefix = fleet ? "drive " + std::to_string(number) + ": " : std::string();
    try {
      units_.push_back(std::make_unique<DriveUnit>(io_, drives[i], number, prefix));
    } catch (const StartupError& e) {
      throw StartupError(prefix + e.what());
    } catch (const UsageError& e) {
      throw UsageError(prefix + e.what());
    }
  }
}

App::~App() { shutdown(); }

void App::start() {
  for (auto& u : units_) u->start();
  for (auto& u : units_) fleet_.add(u->steps());
  clock_ = std::make_unique<ClockDriver>(io_, fleet_, mode_);
  for (auto& u : units_) u->attach_clock(*clock_, &script_runs_);
  // --clock manual: a step waits for every script it woke (scripting.md §8.2); each unit registers
  // its own resume, so all of them are asked — when any has a script run at all (asked after every
  // full step: a fleet of 1000 drives without scripts should not visit 1000 units for it)
  clock_->set_hold([this] {
    if (script_runs_ == 0) return false;
    bool held = false;
    for (auto& u : units_) held = u->script_holds_clock() || held;
    return held;
  });
  clock_->start();
  if (units_.size() == 1) {
    spdlog::info("mcemu {} ready (clock {})", MCEMU_VERSION, mode_.name());
  } else {
    spdlog::info("mcemu {} ready: {} drives (clock {})", MCEMU_VERSION, units_.size(), mode_.name());
  }
}

void App::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  if (clock_) clock_->sync();  // the plant state written at shutdown is the current one
  if (clock_) clock_->stop();
  for (auto& u : units_) u->shutdown();
}

}  // namespace mcemu::server
