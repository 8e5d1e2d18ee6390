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

#include "protocols/line/net/line_server.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/canopen_bus.hpp"
#include "server/drive_unit.hpp"
#include "web/api/fault_gates.hpp"
#include "web/api/router.hpp"

namespace mcemu::server {

namespace asio = boost::asio;

namespace {

std::chrono::milliseconds steady_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now().time_since_epoch());
}

std::string peer_text(const udp_debug::Peer& p) { return p.address + ":" + std::to_string(p.port); }

web::api::SdoPhase phase_of(canopen::SdoFaultPhase p) {
  switch (p) {
    case canopen::SdoFaultPhase::initiate: return web::api::SdoPhase::initiate;
    case canopen::SdoFaultPhase::segment: return web::api::SdoPhase::segment;
    case canopen::SdoFaultPhase::end: break;
  }
  return web::api::SdoPhase::end;
}

}  // namespace

void DriveUnit::wire_transport() {
  auto& faults = router_->transport_faults();
  const std::weak_ptr<DriveUnit*> alive = self_;
  // The router is shared with the HTTP handler and may serve a request after the unit is gone.
  faults.set_applied_listener([this, alive](const web::api::TransportFault& f) {
    if (alive.lock()) trace_->record(web::api::trace_channel(f.kind), trace::Dir::event, web::api::applied_text(f));
  });
  // refgo.disconnect, slcan.disconnect, slcan.rawTx: after the request that created them.
  faults.set_action_listener([this, alive] {
    asio::post(io_, [this, alive] {
      if (alive.lock()) run_transport_actions();
    });
  });

  canopen::Node::Faults node;
  node.sdo.abort = [&faults](std::uint16_t index, std::uint8_t sub,
                             canopen::SdoFaultPhase phase) -> std::optional<std::uint32_t> {
    const auto plan = faults.slcan_sdo_abort(index, sub, phase_of(phase));
    if (!plan) return std::nullopt;
    return plan->code;
  };
  node.sdo.no_reply = [&faults](std::uint16_t index) { return faults.take_sdo_no_reply(index); };
  node.heartbeat_stop = [&faults] { return faults.take_heartbeat_stop(); };
  canopen_->node().set_faults(std::move(node));

  // Held-back node frames come out by a wall-clock timer (slcan.delayTx).
  auto timer = std::make_shared<asio::steady_timer>(io_);
  CanopenBus::Faults bus;
  bus.node_frame = [&faults](const can::Frame& f) { return web::api::node_frame_verdict(faults, f.id); };
  bus.bel = [&faults] { return faults.take_slcan_bel(); };
  bus.wall_now = steady_ms;
  bus.schedule = [this, alive, timer](std::chrono::milliseconds due) {
    timer->expires_at(std::chrono::steady_clock::time_point(due));
    timer->async_wait([this, alive](const boost::system::error_code& ec) {
      if (ec || !alive.lock()) return;
      canopen_->release_delayed();
    });
  };
  bus.trace = [this](const std::string& text) { trace_->record(trace::Channel::slcan, trace::Dir::event, text); };
  canopen_->set_faults(std::move(bus));

  // UDP: every datagram in and out is traced and flickers LINK/ACT (morse-led.md §5.2); udp.drop.
  udp_debug::net::UdpDebugService::Taps taps;
  taps.now = [this] {
    sync();
    return udp_debug::Stamp{core_->time_ms(), utc_iso8601_ms()};
  };
  taps.received = [this](const udp_debug::Peer& from, std::string_view payload, udp_debug::Console::Received r) {
    trace::Flags flags;
    flags.ignored = r != udp_debug::Console::Received::registered;
    trace_->record(trace::Channel::udp, trace::Dir::rx, trace::text_or_hex(payload), 0, peer_text(from), flags);
    leds_.yellow.activity(core_->time_ms());
  };
  taps.may_send = [this, &faults](const udp_debug::Datagram& d) {
    const auto v = web::api::udp_datagram_verdict(faults);
    if (v.action == web::api::Verdict::Action::send) return true;
    trace_->record(trace::Channel::udp, trace::Dir::event,
                   web::api::verdict_text(v, "datagram") + ": " + trace::text_or_hex(d.payload), 0, peer_text(d.to));
    return false;
  };
  taps.sent = [this](const udp_debug::Datagram& d) {
    sync();
    trace_->record(trace::Channel::udp, trace::Dir::tx, trace::text_or_hex(d.payload), 0, peer_text(d.to));
    leds_.yellow.activity(core_->time_ms());
  };
  udp_debug_->set_taps(std::move(taps));
}

void DriveUnit::run_transport_actions() {
  for (const auto& a : router_->transport_faults().drain_actions()) {
    switch (a.kind) {
      case web::api::TransportKind::refgo_disconnect:
        spdlog::info("{}fault injection: closing every RefGo connection", log_prefix_);
        refgo_->close_connections();
        break;
      case web::api::TransportKind::slcan_disconnect:
        spdlog::info("{}fault injection: closing every SLCAN connection", log_prefix_);
        slcan_->close_connections();
        break;
      case web::api::TransportKind::slcan_raw_tx: canopen_->send_raw(a.text); break;
      default: break;
    }
  }
  wake();
}

}  // namespace mcemu::server
