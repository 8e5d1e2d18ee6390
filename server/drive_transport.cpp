// DriveUnit, the transport fault injections (web.md §9, slcan-canopen.md §11.3) and the trace taps
// that are not per connection (udp-debug.md §6; web.md §8.6). The decisions are pure
// (web/api/transport_faults.hpp, web/api/fault_gates.hpp); this file only connects them to the
// adapters: every application is traced on the kind's channel, the one-shot kinds run on the loop
// right after the request that created them, the CANopen node asks for its SDO and heartbeat
// faults, the bus for its node frames, the UDP service for its datagrams.
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>

#include "device/canopen_bus.hpp"
#include "device/fault_gates.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/drive_unit.hpp"

namespace mcemu::server {

namespace asio = boost::asio;

namespace {

std::chrono::milliseconds steady_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch());
}

std::string peer_text(const udp_debug::Peer& p) { return p.address + ":" + std::to_string(p.port); }

device::SdoPhase phase_of(canopen::SdoFaultPhase p) {
  switch (p) {
    case canopen::SdoFaultPhase::initiate: return device::SdoPhase::initiate;
    case canopen::SdoFaultPhase::segment: return device::SdoPhase::segment;
    case canopen::SdoFaultPhase::end: break;
  }
  return device::SdoPhase::end;
}

}  // namespace

void DriveUnit::wire_transport() {
  auto& faults = device_->transport_faults();
  const auto alive = alive_.watch();
  faults.set_applied_listener([this](const device::TransportFault& f) {
    device_->trace().record(device::trace_channel(f.kind), trace::Dir::event, device::applied_text(f));
  });
  // refgo.disconnect, slcan.disconnect, slcan.rawTx: after the request that created them.
  faults.set_action_listener([this, alive] {
    asio::post(io_, [this, alive] {
      if (alive) run_transport_actions();
    });
  });
  if (device_->canopen()) wire_canopen_faults();
  if (udp_debug_) wire_udp_taps();
}

void DriveUnit::wire_canopen_faults() {
  auto& faults = device_->transport_faults();
  const auto alive = alive_.watch();
  auto* canopen = device_->canopen();

  canopen::Node::Faults node;
  node.sdo.abort = [&faults](std::uint16_t index, std::uint8_t sub,
                             canopen::SdoFaultPhase phase) -> std::optional<std::uint32_t> {
    const auto plan = faults.slcan_sdo_abort(index, sub, phase_of(phase));
    if (!plan) return std::nullopt;
    return plan->code;
  };
  node.sdo.no_reply = [&faults](std::uint16_t index) { return faults.take_sdo_no_reply(index); };
  node.heartbeat_stop = [&faults] { return faults.take_heartbeat_stop(); };
  canopen->node().set_faults(std::move(node));

  // Held-back node frames come out by a wall-clock timer (slcan.delayTx).
  auto timer = std::make_shared<asio::steady_timer>(io_);
  device::CanopenBus::Faults bus;
  bus.node_frame = [&faults](const can::Frame& f) { return device::node_frame_verdict(faults, f.id); };
  bus.bel = [&faults] { return faults.take_slcan_bel(); };
  bus.wall_now = steady_ms;
  bus.schedule = [canopen, alive, timer](std::chrono::milliseconds due) {
    timer->expires_at(std::chrono::steady_clock::time_point(due));
    timer->async_wait([canopen, alive](const boost::system::error_code& ec) {
      if (ec || !alive) return;
      canopen->release_delayed();
    });
  };
  bus.trace = [this](const std::string& text) {
    settle();  // a wall-clock timer's line is stamped with the drive's current time
    device_->trace().record(trace::Channel::slcan, trace::Dir::event, text);
  };
  canopen->set_faults(std::move(bus));
}

void DriveUnit::wire_udp_taps() {
  auto& faults = device_->transport_faults();
  auto& trace = device_->trace();
  auto& leds = device_->leds();
  const auto& core = device_->core();

  // UDP: every datagram in and out is traced and flickers LINK/ACT (morse-led.md §5.2); udp.drop.
  udp_debug::net::UdpDebugService::Taps taps;
  taps.now = [this] {
    sync();
    return udp_debug::Stamp{device_->core().time_ms(), utc_iso8601_ms()};
  };
  taps.received = [&trace, &leds, &core](const udp_debug::Peer& from, std::string_view payload,
                                         udp_debug::Console::Received r) {
    trace::Flags flags;
    flags.ignored = r != udp_debug::Console::Received::registered;
    trace.record(trace::Channel::udp, trace::Dir::rx, trace::text_or_hex(payload), 0, peer_text(from), flags);
    leds.yellow.activity(core.time_ms());
  };
  taps.may_send = [&trace, &faults](const udp_debug::Datagram& d) {
    const auto v = device::udp_datagram_verdict(faults);
    if (v.action == device::Verdict::Action::send) return true;
    trace.record(trace::Channel::udp, trace::Dir::event,
                 device::verdict_text(v, "datagram") + ": " + trace::text_or_hex(d.payload), 0, peer_text(d.to));
    return false;
  };
  taps.sent = [this, &trace, &leds, &core](const udp_debug::Datagram& d) {
    sync();
    trace.record(trace::Channel::udp, trace::Dir::tx, trace::text_or_hex(d.payload), 0, peer_text(d.to));
    leds.yellow.activity(core.time_ms());
  };
  udp_debug_->set_taps(std::move(taps));
}

void DriveUnit::run_transport_actions() {
  for (const auto& a : device_->transport_faults().drain_actions()) {
    switch (a.kind) {
      case device::TransportKind::refgo_disconnect:
        if (!refgo_) break;
        spdlog::info("{}fault injection: closing every RefGo connection", log_prefix_);
        refgo_->close_connections();
        break;
      case device::TransportKind::slcan_disconnect:
        if (!slcan_) break;
        spdlog::info("{}fault injection: closing every SLCAN connection", log_prefix_);
        slcan_->close_connections();
        break;
      case device::TransportKind::slcan_raw_tx:
        if (device_->canopen()) device_->canopen()->send_raw(a.text);
        break;
      default: break;
    }
  }
  wake();
}

}  // namespace mcemu::server
