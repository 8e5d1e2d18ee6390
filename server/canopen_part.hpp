// The CANopen bus of one drive as a part of its step (sim/drive_steps.hpp): stepped after the
// drive and the shell's event hand-off (App::step order), quiet until the node's next deadline
// (boot-up, heartbeat, TPDO event/inhibit timers, SDO timeout, life guarding, pending output).
// A skip advances the bus time and runs the node once at the end, which does nothing when no
// deadline fell inside (the node's advance() at a time before every deadline is a no-op).
#pragma once

#include <chrono>

#include "server/canopen_bus.hpp"
#include "sim/drive_steps.hpp"

namespace mcemu::server {

inline sim::FunctionPart canopen_part(CanopenBus& bus) {
  return sim::FunctionPart(
      [&bus] { bus.step(); },
      [&bus]() -> std::uint64_t {
        const auto d = bus.node().next_deadline();
        if (!d) return sim::k_forever;
        const auto now = bus.now().count();
        return d->count() > now ? static_cast<std::uint64_t>(d->count() - now - 1) : 0;
      },
      [&bus](std::uint64_t n) { bus.step(std::chrono::milliseconds(static_cast<std::int64_t>(n))); });
}

}  // namespace mcemu::server
