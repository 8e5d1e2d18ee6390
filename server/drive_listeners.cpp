// DriveUnit, the network side of the line protocols and UDP: the RefGo and SLCAN listeners of the
// personality, the client session every connection gets (server/client_session.hpp), the UDP socket.
#include <spdlog/spdlog.h>

#include <boost/asio/ip/address.hpp>

#include "device/fault_gates.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/line/net/pty_server.hpp"
#include "protocols/refgo/session.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/drive_unit.hpp"

namespace mcemu::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using udp = asio::ip::udp;

void DriveUnit::bind_listeners() {
  boost::system::error_code ec;
  const auto address = asio::ip::make_address(settings_.bind, ec);
  if (ec) throw UsageError("invalid value '" + settings_.bind + "' for --bind (" + ec.message() + ")");

  const auto make_line = [&](const std::string& name, const std::string& label, std::uint16_t port,
                             const std::string& flag, std::size_t max_clients, bool close_on_overflow,
                             line::net::SessionFactory factory) {
    line::net::LineServerOptions o;
    o.name = name;
    o.flag = flag;
    o.max_clients = max_clients;
    o.close_on_overflow = close_on_overflow;
    o.idle_timeout = settings_.idle_timeout;
    o.ids = conn_ids_;
    if (close_on_overflow) {
      o.pause_above = name == "faulhaber" ? device_->faulhaber_config().port.queue_limit_bytes
                                          : device_->slcan_config().queue_limit_bytes;
    }
    try {
      return std::make_unique<line::net::LineServer>(io_, tcp::endpoint(address, port), o, std::move(factory));
    } catch (const boost::system::system_error& e) {
      bind_failed(label, settings_.bind, port, flag, e);
    }
  };
  const auto& personality = device_->personality();
  if (personality.refgo) {
    refgo_ = make_line("refgo", "RefGo", settings_.refgo_port, "--refgo-port", settings_.refgo_max_clients, false,
                       [this](const line::net::PeerInfo& p) { return make_refgo_session(p); });
  }
  if (personality.canopen) {
    slcan_ = make_line("slcan", "SLCAN", settings_.slcan_port, "--slcan-port", settings_.slcan_max_clients, true,
                       [this](const line::net::PeerInfo& p) { return make_slcan_session(p); });
  }
  if (personality.faulhaber) {
    auto port = make_line("faulhaber", "FAULHABER", settings_.faulhaber_port, "--faulhaber-port",
                          settings_.faulhaber_max_clients, true,
                          [this](const line::net::PeerInfo& p) { return make_faulhaber_session(p); });
    faulhaber_ = std::move(port);
    if (settings_.faulhaber_pty) open_faulhaber_pty();
  }
  if (personality.udp_debug) bind_udp(address);
  build_web(address);
  wire_transport();
}

void DriveUnit::bind_udp(const asio::ip::address& address) {
  try {
    udp_ = std::make_unique<udp::socket>(io_);
    udp_->open(address.is_v6() ? udp::v6() : udp::v4());
    // SO_REUSEADDR lets a host tool such as Fullmo's UdpMonitor bind the same port (udp-debug.md §1.2).
    udp_->set_option(udp::socket::reuse_address(true));
    udp_->bind(udp::endpoint(address, settings_.udp_port));
  } catch (const boost::system::system_error& e) {
    bind_failed("UDP debug output", settings_.bind, settings_.udp_port, "--udp-port", e);
  }
  udp_debug_ = std::make_shared<udp_debug::net::UdpDebugService>(io_, *udp_);
  udp_debug_->set_notes(device_->settings().udp_emulator_notes);
}

// ---- protocol engines behind the listeners ----------------------------------------------------

// The hooks every client session of this unit shares; `notes`: connect/disconnect UDP notes.
ClientSession::Hooks DriveUnit::client_hooks(bool notes) {
  ClientSession::Hooks h;
  h.sync = [this] { sync(); };
  h.wake = [this] { wake(); };
  auto& leds = device_->leds();
  const auto& core = device_->core();
  h.link = [&leds, &core](bool opened) {
    if (opened) {
      leds.yellow.connection_opened(core.time_ms());
    } else {
      leds.yellow.connection_closed(core.time_ms());
    }
  };
  h.activity = [&leds, &core] { leds.yellow.activity(core.time_ms()); };
  if (notes && udp_debug_) {
    h.note = [weak = std::weak_ptr<udp_debug::net::UdpDebugService>(udp_debug_)](const std::string& text) {
      if (auto u = weak.lock()) u->note(text);
    };
  }
  return h;
}

// The trace of one connection (refgo.md §13, slcan-canopen.md §11.2): channel, conn and peer bound.
std::function<void(trace::Dir, std::string_view, trace::Flags)> DriveUnit::connection_trace(
    trace::Channel channel, const line::net::PeerInfo& peer) {
  // A session can outlive the unit (the adapter's last handlers): then nothing is recorded.
  return [ring = &device_->trace(), alive = alive_.watch(), channel, conn = peer.id, address = peer.address](
             trace::Dir dir, std::string_view text, trace::Flags flags) {
    if (alive) ring->record(channel, dir, text, conn, address, flags);
  };
}

std::unique_ptr<line::StreamSession> DriveUnit::make_refgo_session(const line::net::PeerInfo& peer) {
  auto inner = std::make_unique<refgo::Session>(*device_->refgo());
  auto* refgo = inner.get();
  auto& lint = device_->lint();
  auto hooks = client_hooks(true);
  hooks.trace = connection_trace(trace::Channel::refgo, peer);
  hooks.reply_verdict = [this] { return device::refgo_reply_verdict(device_->transport_faults()); };
  // The master lint (docs/lint.md §4.4): each reply as it goes out (after refgo.delay) or is dropped.
  if (lint.active()) {
    hooks.replied = [&lint, conn = peer.id](bool sent) {
      lint.reply(lint::Link::refgo, conn, sent ? lint::ReplyKind::response : lint::ReplyKind::none);
    };
  }
  auto client = std::make_unique<ClientSession>(lint.wrap(std::move(inner), peer.id), alive_.watch(), std::move(hooks),
                                                "refgo client " + peer.address, io_.get_executor());
  refgo->set_reply_sink([c = client.get()](std::string reply) { c->reply(std::move(reply)); });
  refgo::Session::Observer observer;
  // Over-long lines are traced as their first 64 bytes (web.md §8.6). The lint gets every line as a
  // request; one that only a script gets (refgo.md §5) expects no reply from the drive.
  observer.received = [c = client.get(), lint = lint.active() ? &lint : nullptr, interpreter = device_->refgo(),
                       alive = alive_.watch(), conn = peer.id](const line::Line& l) {
    trace::Flags f;
    f.overlong = l.overlong;
    c->trace(trace::Dir::rx, std::string_view(l.raw).substr(0, l.overlong ? 64 : std::string_view::npos), f);
    if (lint && alive) {
      lint->request(lint::Link::refgo, conn, l.overlong || interpreter->attachment().route(l.text).execute);
    }
  };
  observer.to_script = [c = client.get()](std::string_view text, bool discarded) {
    trace::Flags f;
    f.to_script = true;
    f.discarded = discarded;
    c->trace(trace::Dir::event, text, f);
  };
  refgo->set_observer(std::move(observer));
  return client;
}

// --faulhaber-pty: the pseudo-terminal is one more connection of the FAULHABER port (faulhaber.md §2.2).
void DriveUnit::open_faulhaber_pty() {
  line::net::PtyOptions o;
  o.link_path = *settings_.faulhaber_pty;
  o.flag = "--faulhaber-pty";
  o.line.name = "faulhaber";
  o.line.close_on_overflow = true;
  o.line.pause_above = device_->faulhaber_config().port.queue_limit_bytes;
  try {
    faulhaber_pty_ = std::make_unique<line::net::PtyServer>(
        io_, std::move(o), [this](const line::net::PeerInfo& p) { return make_faulhaber_session(p); });
  } catch (const std::runtime_error& e) {
    throw StartupError(e.what());
  }
}

// A FAULHABER connection (faulhaber.md §2): the port's session, every frame on the trace channel
// faulhaber with its hex and a decoded summary (the texts are only valid during the call). The ring
// records every event (it has no "off"), so the line is built in a buffer the callback keeps and
// reuses: no string per frame; the ring copies it into its own slot.
std::unique_ptr<line::StreamSession> DriveUnit::make_faulhaber_session(const line::net::PeerInfo& peer) {
  const auto tap = connection_trace(trace::Channel::faulhaber, peer);
  faulhaber::Port::Trace frames = [tap, text = std::string()](const faulhaber::TraceEvent& e) mutable {
    using K = faulhaber::TraceEvent::Kind;
    const auto dir = e.kind == K::rx ? trace::Dir::rx : e.kind == K::tx ? trace::Dir::tx : trace::Dir::event;
    faulhaber::trace_line(e, text);
    tap(dir, text, {});
  };
  auto& lint = device_->lint();  // the master lint reads requests and replies from the trace
  auto session = device_->faulhaber_port()->make_session(lint.faulhaber_trace(peer.id, std::move(frames)));
  auto hooks = client_hooks(false);
  hooks.trace = tap;
  return std::make_unique<ClientSession>(lint.wrap(std::move(session), peer.id), alive_.watch(), std::move(hooks),
                                         "faulhaber client " + peer.address, io_.get_executor());
}

std::unique_ptr<line::StreamSession> DriveUnit::make_slcan_session(const line::net::PeerInfo& peer) {
  const auto tap = connection_trace(trace::Channel::slcan, peer);
  auto session = device_->canopen()->make_session([tap](const slcan::TraceEvent& e) {
    const auto dir = e.dir == slcan::TraceEvent::Dir::rx   ? trace::Dir::rx
                     : e.dir == slcan::TraceEvent::Dir::tx ? trace::Dir::tx
                                                           : trace::Dir::event;
    trace::Flags f;
    f.overlong = e.overlong;
    tap(dir, e.text, f);
  });
  auto hooks = client_hooks(false);
  hooks.trace = tap;
  return std::make_unique<ClientSession>(device_->lint().wrap(std::move(session), peer.id), alive_.watch(),
                                         std::move(hooks), "slcan client " + peer.address, io_.get_executor());
}

}  // namespace mcemu::server
