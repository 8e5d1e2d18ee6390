// The composition root of mcemu: the drives of this process (one DriveUnit each, server/drive_unit.hpp)
// and the one clock that steps them all (spec README: one process, one io_context, one thread).
// `--drives N`, `--port-step S` and `--fleet FILE` decide how many units there are and their
// addresses (server/fleet.hpp); every unit is independent of the others.
#pragma once

#include <boost/asio/io_context.hpp>
#include <memory>
#include <vector>

#include "server/drive_unit.hpp"
#include "server/settings.hpp"
#include "sim/steppable.hpp"

namespace mcemu::server {

class ClockDriver;

class App {
 public:
  // Builds every drive and binds all ports; throws StartupError or UsageError.
  App(boost::asio::io_context& io, const Settings& settings);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  void start();     // every unit starts, then the clock
  void shutdown();  // the clock stops, then every unit shuts down

  std::size_t size() const { return units_.size(); }
  DriveUnit& unit(std::size_t i) { return *units_.at(i); }

 private:
  boost::asio::io_context& io_;
  // Units whose script engine has a run (DriveUnit::attach_clock): only they can hold the manual
  // clock. Declared before units_, which update it until they are gone.
  std::size_t script_runs_ = 0;
  std::vector<std::unique_ptr<DriveUnit>> units_;
  sim::Fleet fleet_;
  sim::ClockMode mode_;
  std::unique_ptr<ClockDriver> clock_;
  bool shut_down_ = false;
};

}  // namespace mcemu::server
