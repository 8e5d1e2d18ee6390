// One idle drive in-process, for bench/idle_cpu.sh: the drive bundle as the server composes it (I/O
// functions and core, fault injections, scope, RefGo programs, the event hand-off with the LEDs, the
// CANopen bus) on one io_context, driven by the clock driver either the old way ("old": a full
// step every 1 ms) or the new way ("new": sim::DriveSteps, sleeping until the next needed step).
// No listeners: idle sockets cost nothing either way. Runs for the given seconds (default: until
// killed) and prints the clock's counters at the end. A benchmark, not a test.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "server/clock_driver.hpp"
#include "sim/drive_steps.hpp"
#include "tests/support/device_fixture.hpp"

using namespace mcemu;

int main(int argc, char** argv) {
  if (argc < 2 || (std::strcmp(argv[1], "old") != 0 && std::strcmp(argv[1], "new") != 0)) {
    std::fprintf(stderr, "usage: idle_cpu_harness old|new [seconds] [heartbeat_ms]\n");
    return 2;
  }
  const bool old_way = std::strcmp(argv[1], "old") == 0;
  const int seconds = argc > 2 ? std::atoi(argv[2]) : 0;
  const int heartbeat_ms = argc > 3 ? std::atoi(argv[3]) : 0;

  // The bundle as the server builds it (tests/support/device_fixture.hpp: storage in memory).
  testing::DeviceOptions options;
  options.keep_events = false;
  testing::DeviceFixture fx("MC349", std::move(options));
  auto& steps = fx.device().steps();
  if (heartbeat_ms > 0) fx.W(0x1017, 0, heartbeat_ms);
  fx.device().power_up_network();  // as DriveUnit::start: the drive runs to the node's boot-up first

  boost::asio::io_context ctx;
  std::unique_ptr<server::ClockDriver> clock;
  if (old_way) {
    clock = std::make_unique<server::ClockDriver>(ctx, [&] { steps.step(); });
  } else {
    clock = std::make_unique<server::ClockDriver>(ctx, steps, sim::ClockMode{});
  }
  clock->start();
  boost::asio::signal_set signals(ctx, SIGTERM, SIGINT);
  signals.async_wait([&](auto, int) { ctx.stop(); });
  boost::asio::steady_timer end(ctx);
  if (seconds > 0) {
    end.expires_after(std::chrono::seconds(seconds));
    end.async_wait([&](auto) { ctx.stop(); });
  }
  ctx.run();
  clock->sync();  // drive time is lazy while idle: bring it to now before reporting
  std::printf("%s: drive time %llu ms, clock steps %llu, full steps %llu, wake-ups %llu\n", argv[1],
              static_cast<unsigned long long>(fx.core().time_ms()), static_cast<unsigned long long>(clock->steps()),
              static_cast<unsigned long long>(clock->full_steps()), static_cast<unsigned long long>(clock->wake_ups()));
  return 0;
}
