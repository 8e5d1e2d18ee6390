// One idle drive in-process, for bench/idle_cpu.sh: the drive as the server composes it (I/O
// functions and core, fault injections, RefGo programs, the event hand-off with the LEDs, the
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

#include "drive/led/leds.hpp"
#include "drive/model/model_preset.hpp"
#include "server/canopen_bus.hpp"
#include "server/canopen_part.hpp"
#include "server/clock_driver.hpp"
#include "sim/drive_steps.hpp"

using namespace mcemu;

int main(int argc, char** argv) {
  if (argc < 2 || (std::strcmp(argv[1], "old") != 0 && std::strcmp(argv[1], "new") != 0)) {
    std::fprintf(stderr, "usage: idle_cpu_harness old|new [seconds] [heartbeat_ms]\n");
    return 2;
  }
  const bool old_way = std::strcmp(argv[1], "old") == 0;
  const int seconds = argc > 2 ? std::atoi(argv[2]) : 0;
  const int heartbeat_ms = argc > 3 ? std::atoi(argv[3]) : 0;

  const auto preset = *model::find_preset("MC349");
  od::ObjectDictionary od(preset);
  core::DriveCore core(preset, od);
  iofunc::IoFunctions io(od, core);
  web::api::FaultInjections faults(od, core);
  refgo::Interpreter refgo(od, core);
  led::Leds leds;
  std::unique_ptr<server::CanopenBus> bus;
  const auto hand_off = [&] {
    io.drain_diagnostics();
    for (const auto& e : core.drain_events()) {
      if (const auto* emcy = std::get_if<core::Emcy>(&e)) bus->node().emit_emcy(emcy->code, emcy->reg, emcy->data);
    }
    leds.update_status(core, od);
  };
  canopen::Node::Hooks hooks;
  hooks.after_od_write = hand_off;
  bus = std::make_unique<server::CanopenBus>(od, slcan::SlcanConfig{}, canopen::CanopenConfig{}, std::move(hooks));
  if (heartbeat_ms > 0) od.write(0x1017, 0, od::Value{std::int64_t{heartbeat_ms}}, od::Origin::sdo);

  sim::FaultsPart faults_part(faults, core);
  sim::RefgoPart refgo_part(refgo, core);
  sim::HookPart events_part(hand_off);
  sim::FunctionPart canopen_part = server::canopen_part(*bus);
  sim::DriveSteps steps(od, io, core);
  steps.add(faults_part);
  steps.add(refgo_part);
  steps.add(events_part);
  steps.add(canopen_part);

  io.power_on();
  leds.power_up(led::address_of(od));
  bus->start();
  // as App::start: run the drive to the node's boot-up before the clock starts
  for (int i = 0; i < 1000 && bus->node().state() == canopen::NmtState::initialising; ++i) steps.step();

  boost::asio::io_context ctx;
  std::unique_ptr<server::ClockDriver> clock;
  if (old_way) {
    clock = std::make_unique<server::ClockDriver>(ctx, [&] { steps.step(); });
  } else {
    clock = std::make_unique<server::ClockDriver>(ctx, steps, server::ClockMode{});
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
              static_cast<unsigned long long>(core.time_ms()), static_cast<unsigned long long>(clock->steps()),
              static_cast<unsigned long long>(clock->full_steps()), static_cast<unsigned long long>(clock->wake_ups()));
  return 0;
}
