// mcemu: emulator of a Fullmo MovingCap Ethernet servo drive. Parses the command line, builds the
// App on one io_context and runs it until SIGINT/SIGTERM.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <ctime>
#include <iostream>

#include "drive/od/dictionary.hpp"
#include "protocols/canopen/eds.hpp"
#include "server/app.hpp"
#include "server/drive_image.hpp"
#include "server/fleet.hpp"
#include "server/settings.hpp"

namespace {

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("mcemu");
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e [%l] %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::flush_on(spdlog::level::trace);
}

// Every connection is a file descriptor: the soft limit (often 1024) would stop --max-clients 1000
// short of its promise, so it is raised to the hard limit at start.
void raise_file_limit() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return;
  if (limit.rlim_cur < limit.rlim_max) {
    const auto before = limit.rlim_cur;
    limit.rlim_cur = limit.rlim_max;
    if (::setrlimit(RLIMIT_NOFILE, &limit) != 0) {
      spdlog::warn("cannot raise the file descriptor limit above {}", before);
      return;
    }
  }
  spdlog::debug("file descriptor limit {}", limit.rlim_cur);
}

int run(const mcemu::server::Settings& settings) {
  raise_file_limit();
  boost::asio::io_context io(1);
  mcemu::server::App app(io, settings);
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int sig) {
    if (ec) return;
    spdlog::info("signal {}: shutting down", sig);
    app.shutdown();
    io.stop();
  });
  app.start();
  io.run();
  app.shutdown();
  spdlog::info("stopped");
  return 0;
}

int start(int argc, char** argv) {
  mcemu::server::Settings settings;
  try {
    settings = mcemu::server::parse_command_line(std::vector<std::string>(argv + 1, argv + argc));
    if (settings.help) {
      std::cout << mcemu::server::help_text();
      return 0;
    }
    if (settings.version) {
      std::cout << "mcemu " << MCEMU_VERSION << "\n";
      return 0;
    }
    if (settings.dump_od || settings.dump_eds) {                // the preset's dictionary; no state, no ports
      const auto drive = mcemu::server::dump_target(settings);  // --drive K of --drives/--fleet
      const auto preset = mcemu::server::make_preset(drive);
      mcemu::od::ObjectDictionary od(preset);
      mcemu::server::apply_config_objects(od, drive.config);
      if (settings.dump_eds) {
        std::cout << mcemu::canopen::make_eds(od, mcemu::server::eds_info(preset));
      } else {
        std::cout << mcemu::server::dump_od(od, preset.name).dump(1) << "\n";
      }
      return 0;
    }
  } catch (const mcemu::server::UsageError& e) {
    std::cerr << "mcemu: " << e.what() << "\n";
    return 2;
  }
  setup_logging(settings.log_level);
  try {
    return run(settings);
  } catch (const mcemu::server::UsageError& e) {
    spdlog::critical("{}", e.what());
    return 2;
  } catch (const mcemu::server::StartupError& e) {
    spdlog::critical("{}", e.what());
    return 1;
  } catch (const std::exception& e) {
    spdlog::critical("start-up failed: {}", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);  // a failed write is an ordinary disconnect (design.md)
  try {
    return start(argc, argv);
  } catch (const std::exception& e) {  // e.g. --dump-od failing to write, or a logger that cannot start
    std::cerr << "mcemu: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "mcemu: unexpected failure\n";
  }
  return 1;
}
