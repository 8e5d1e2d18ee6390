// DriveUnit, the network side of the line protocols and UDP: the RefGo and SLCAN listeners, the
// session every client connection gets (clock sync, LINK/ACT LED, connect notes), the UDP socket.
#include <spdlog/spdlog.h>

#include <boost/asio/ip/address.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <optional>

#include "drive/led/leds.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/session.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/canopen_bus.hpp"
#include "server/drive_unit.hpp"
#include "trace/trace.hpp"
#include "web/api/fault_gates.hpp"
#include "web/api/router.hpp"

namespace mcemu::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using udp = asio::ip::udp;

namespace {

// The session of one RefGo or SLCAN client as the drive sees it: drive time is brought up to date
// before its input runs (the clock sleeps while the drive is idle, docs/clock.md) and the clock is
// woken after it (a command may have started a move); the connection counts for the yellow
// LINK/ACT LED and its traffic flickers it (morse-led.md §5); connect and disconnect are UDP
// emulator notes (udp-debug.md §4.7) and trace events (web.md §8.6). The protocol behaviour is the
// inner session's. With a reply verdict (RefGo, web.md §9), each reply unit the inner session hands
// to reply() is traced and sent, dropped (refgo.noReply) or held back in wall time (refgo.delay)
// by the pure decision of web/api/fault_gates.hpp; a timer brings held-back replies out in order.
class ClientSession final : public line::StreamSession {
 public:
  struct Hooks {
    std::function<void()> sync;
    std::function<void()> wake;
    std::function<void(bool opened)> link;              // LED: a counted connection opened / closed
    std::function<void()> activity;                     // LED: traffic
    std::function<void(const std::string& text)> note;  // empty: no notes (udp-debug.md §4.7 names RefGo)
    // This connection's trace (channel, conn and peer bound); empty: no trace.
    std::function<void(trace::Dir dir, std::string_view text, trace::Flags flags)> trace;
    std::function<web::api::Verdict()> reply_verdict;  // empty: replies pass through the inner session
  };

  // `unit` is the DriveUnit's liveness token: a connection's last handler may run after the unit
  // is gone, and then nothing is told.
  ClientSession(std::unique_ptr<line::StreamSession> inner, std::weak_ptr<DriveUnit*> unit, Hooks hooks,
                std::string what, asio::any_io_executor executor)
      : inner_(std::move(inner)),
        unit_(std::move(unit)),
        hooks_(std::move(hooks)),
        what_(std::move(what)),
        timer_(std::move(executor)) {
    inner_->set_wake([this] { wake(); });
    if (alive()) {
      hooks_.sync();
      hooks_.link(true);
      if (hooks_.note) hooks_.note(what_ + " connected");
      trace(trace::Dir::event, "connect");
    }
  }
  ~ClientSession() override {
    if (alive()) {
      hooks_.sync();
      hooks_.link(false);
      if (hooks_.note) hooks_.note(what_ + " disconnected");
      trace(trace::Dir::event, "disconnect");
    }
  }
  ClientSession(const ClientSession&) = delete;
  ClientSession& operator=(const ClientSession&) = delete;

  void receive(std::string_view bytes) override {
    if (!alive()) return inner_->receive(bytes);
    hooks_.sync();
    hooks_.activity();
    inner_->receive(bytes);
    hooks_.wake();
  }
  std::string take_output() override {
    std::string out = inner_->take_output();
    release(out);
    if (!out.empty() && alive()) hooks_.activity();
    return out;
  }
  void peer_closed() override {
    if (alive()) hooks_.sync();
    inner_->peer_closed();
    if (alive()) hooks_.wake();
  }
  bool finished() const override { return inner_->finished() && ready_.empty() && held_.empty(); }
  bool paused() const override { return inner_->paused(); }
  void closing(std::string_view reason) override {
    trace(trace::Dir::event, reason);
    inner_->closing(reason);
  }

  // One reply unit of the inner session (refgo::Session's reply sink).
  void reply(std::string text) {
    const auto v = hooks_.reply_verdict && alive() ? hooks_.reply_verdict() : web::api::Verdict{};
    if (v.action == web::api::Verdict::Action::drop) {
      trace(trace::Dir::event, web::api::verdict_text(v, "reply") + ": " + text);
      return;
    }
    if (v.action == web::api::Verdict::Action::delay) trace(trace::Dir::event, web::api::verdict_text(v, "reply"));
    if (v.action == web::api::Verdict::Action::send && held_.empty()) {  // the common case: no clock read
      trace(trace::Dir::tx, text);
      ready_ += text;
      return;
    }
    const auto now = wall_now();
    if (auto at_once = held_.push(std::move(text), now, now + v.delay)) {
      trace(trace::Dir::tx, *at_once);
      ready_ += *at_once;
    }
  }

  void trace(trace::Dir dir, std::string_view text, trace::Flags flags = {}) const {
    if (hooks_.trace && alive()) hooks_.trace(dir, text, flags);
  }

 private:
  using Ms = std::chrono::milliseconds;
  static Ms wall_now() { return std::chrono::duration_cast<Ms>(std::chrono::steady_clock::now().time_since_epoch()); }
  bool alive() const { return !unit_.expired(); }

  // Appends the replies that may go now; arms the timer for the next held-back one.
  void release(std::string& out) {
    if (held_.empty()) {
      out += std::exchange(ready_, {});
      return;
    }
    auto due_now = held_.pop_due(wall_now());
    if (!due_now.empty() && alive()) hooks_.sync();  // the trace shows the drive time of sending
    for (auto& r : due_now) {
      trace(trace::Dir::tx, r);
      ready_ += r;
    }
    out += std::exchange(ready_, {});
    const auto due = held_.next_due();
    if (!due || (armed_ && *armed_ == *due)) return;
    armed_ = due;
    timer_.expires_at(std::chrono::steady_clock::time_point(*due));
    timer_.async_wait([weak = std::weak_ptr<bool>(token_), this](const boost::system::error_code& ec) {
      if (ec || weak.expired()) return;
      armed_.reset();
      wake();  // the adapter collects: take_output() releases what is due
    });
  }

  std::unique_ptr<line::StreamSession> inner_;
  std::weak_ptr<DriveUnit*> unit_;
  Hooks hooks_;
  std::string what_;
  std::string ready_;                      // replies that may be sent, in order
  web::api::DelayLine<std::string> held_;  // replies held back by refgo.delay
  asio::steady_timer timer_;
  std::optional<Ms> armed_;                                     // the due time the timer waits for
  std::shared_ptr<bool> token_ = std::make_shared<bool>(true);  // handlers check this is alive
};

}  // namespace

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
    if (close_on_overflow) o.pause_above = slcan_config_.queue_limit_bytes;
    try {
      return std::make_unique<line::net::LineServer>(io_, tcp::endpoint(address, port), o, std::move(factory));
    } catch (const boost::system::system_error& e) {
      bind_failed(label, settings_.bind, port, flag, e);
    }
  };
  refgo_ = make_line("refgo", "RefGo", settings_.refgo_port, "--refgo-port", settings_.refgo_max_clients, false,
                     [this](const line::net::PeerInfo& p) { return make_refgo_session(p); });
  slcan_ = make_line("slcan", "SLCAN", settings_.slcan_port, "--slcan-port", settings_.slcan_max_clients, true,
                     [this](const line::net::PeerInfo& p) { return make_slcan_session(p); });
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
  build_web(address);
  udp_debug_->set_notes(router_->settings().udp_emulator_notes);
  wire_transport();
}

// ---- protocol engines behind the listeners ----------------------------------------------------

namespace {

ClientSession::Hooks client_hooks(std::function<void()> sync, std::function<void()> wake, led::Leds& leds,
                                  const core::DriveCore& core,
                                  const std::shared_ptr<udp_debug::net::UdpDebugService>& udp) {
  ClientSession::Hooks h;
  h.sync = std::move(sync);
  h.wake = std::move(wake);
  h.link = [&leds, &core](bool opened) {
    if (opened) {
      leds.yellow.connection_opened(core.time_ms());
    } else {
      leds.yellow.connection_closed(core.time_ms());
    }
  };
  h.activity = [&leds, &core] { leds.yellow.activity(core.time_ms()); };
  if (udp) {
    h.note = [weak = std::weak_ptr<udp_debug::net::UdpDebugService>(udp)](const std::string& text) {
      if (auto u = weak.lock()) u->note(text);
    };
  }
  return h;
}

}  // namespace

// The trace of one connection (refgo.md §13, slcan-canopen.md §11.2): channel, conn and peer bound.
std::function<void(trace::Dir, std::string_view, trace::Flags)> DriveUnit::connection_trace(
    trace::Channel channel, const line::net::PeerInfo& peer) {
  // A session can outlive the unit (the adapter's last handlers): then nothing is recorded.
  return [ring = trace_.get(), alive = std::weak_ptr<DriveUnit*>(self_), channel, conn = peer.id,
          address = peer.address](trace::Dir dir, std::string_view text, trace::Flags flags) {
    if (!alive.expired()) ring->record(channel, dir, text, conn, address, flags);
  };
}

std::unique_ptr<line::StreamSession> DriveUnit::make_refgo_session(const line::net::PeerInfo& peer) {
  auto inner = std::make_unique<refgo::Session>(*refgo_interpreter_);
  auto* refgo = inner.get();
  auto hooks = client_hooks([this] { sync(); }, [this] { wake(); }, leds_, *core_, udp_debug_);
  hooks.trace = connection_trace(trace::Channel::refgo, peer);
  hooks.reply_verdict = [this] { return web::api::refgo_reply_verdict(router_->transport_faults()); };
  auto client = std::make_unique<ClientSession>(std::move(inner), self_, std::move(hooks),
                                                "refgo client " + peer.address, io_.get_executor());
  refgo->set_reply_sink([c = client.get()](std::string reply) { c->reply(std::move(reply)); });
  refgo::Session::Observer observer;
  // Over-long lines are traced as their first 64 bytes (web.md §8.6).
  observer.received = [c = client.get()](const line::Line& l) {
    trace::Flags f;
    f.overlong = l.overlong;
    c->trace(trace::Dir::rx, std::string_view(l.raw).substr(0, l.overlong ? 64 : std::string_view::npos), f);
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

std::unique_ptr<line::StreamSession> DriveUnit::make_slcan_session(const line::net::PeerInfo& peer) {
  const auto tap = connection_trace(trace::Channel::slcan, peer);
  auto session = canopen_->make_session([tap](const slcan::TraceEvent& e) {
    const auto dir = e.dir == slcan::TraceEvent::Dir::rx   ? trace::Dir::rx
                     : e.dir == slcan::TraceEvent::Dir::tx ? trace::Dir::tx
                                                           : trace::Dir::event;
    trace::Flags f;
    f.overlong = e.overlong;
    tap(dir, e.text, f);
  });
  auto hooks = client_hooks([this] { sync(); }, [this] { wake(); }, leds_, *core_, nullptr);
  hooks.trace = tap;
  return std::make_unique<ClientSession>(std::move(session), self_, std::move(hooks), "slcan client " + peer.address,
                                         io_.get_executor());
}

}  // namespace mcemu::server
