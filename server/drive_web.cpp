// DriveUnit, the web side (web.md): the JSON API's services, the HTTP server with its observer
// (trace channel http, the LINK/ACT LED of page connections) and the WebSocket hub's sources.
#include <spdlog/spdlog.h>

#include <algorithm>

#include "device/scope.hpp"
#include "drive/od/objects.hpp"
#include "protocols/canopen/eds.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/line/net/pty_server.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_image.hpp"
#include "server/drive_unit.hpp"
#include "trace/trace.hpp"
#include "web/api/led_view.hpp"
#include "web/api/router.hpp"
#include "web/api/trace_export.hpp"
#include "web/net/http_server.hpp"

namespace mcemu::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

bool is_api(std::string_view target) { return target.rfind("/api/", 0) == 0; }

}  // namespace

void DriveUnit::build_web(const asio::ip::address& address) {
  auto& dev = *device_;
  web::api::Services services;
  services.info = [this] {
    web::api::Info i;
    i.version = MCEMU_VERSION;
    const auto& preset = device_->preset();
    i.model = preset.name;
    i.display_name = preset.identity.display_name;
    i.device_name = preset.identity.device_name;
    i.software_version = preset.identity.software_version;
    i.serial = preset.identity.serial;
    if (device_->od().find(od::k_device_info, od::k_device_info_serial))
      i.serial = static_cast<std::uint32_t>(device_->od().number(od::k_device_info, od::k_device_info_serial));
    i.ip = device_->active_ip();
    i.mask = device_->active_mask();
    i.bind = settings_.bind;
    if (refgo_) i.refgo_port = refgo_->port();
    if (slcan_) i.slcan_port = slcan_->port();
    i.http_port = http_->port();
    if (udp_) i.udp_port = udp_->local_endpoint().port();
    if (faulhaber_) i.faulhaber_port = faulhaber_->port();
    if (faulhaber_pty_) i.faulhaber_pty = faulhaber_pty_->link_path();
    i.state_dir = settings_.state_dir;
    return i;
  };
  services.factory = [&dev](std::uint16_t index, std::uint8_t sub) { return dev.factory_value(index, sub); };
  services.eds = [&dev] { return canopen::make_eds(*dev.factory_dictionary(), eds_info(dev.preset())); };
  services.clock = [this] {
    web::api::ClockInfo c;
    if (clock_) {
      c.mode = clock_->mode().kind == sim::ClockMode::Kind::real     ? "real"
               : clock_->mode().kind == sim::ClockMode::Kind::scaled ? "scaled"
                                                                     : "manual";
      c.scale = clock_->mode().kind == sim::ClockMode::Kind::manual ? 0.0 : clock_->scale();
    }
    return c;
  };
  services.advance_clock = [this, &dev](std::uint64_t ms, std::function<void(std::uint64_t)> done) {
    if (!clock_ || !clock_->advance(ms, [&dev, done] { done(dev.core().time_ms()); })) done(dev.core().time_ms());
  };
  services.power_cycle = [this](std::function<void()> done) { power_cycle(std::move(done)); };
  if (refgo_) services.refgo_clients = [this] { return static_cast<int>(refgo_->connection_count()); };
  if (udp_debug_) {
    services.udp_listeners = [this] { return static_cast<int>(udp_debug_->console().listeners().size()); };
    services.udp = [this] {
      web::api::UdpView v;
      const auto& console = udp_debug_->console();
      for (const auto& l : console.listeners()) {
        v.listeners.push_back({l.peer.address, l.peer.port, l.registered.drive_ms, l.registered.wall});
      }
      v.backlog_bytes = console.backlog_bytes();
      v.backlog_messages = console.backlog_messages();
      const auto& c = udp_debug_->counters();
      v.datagrams_sent = c.datagrams_sent;
      v.datagrams_dropped = c.datagrams_dropped;
      v.datagrams_received = c.datagrams_received;
      v.ignored_payloads = console.ignored();
      v.messages.assign(udp_debug_->history().begin(), udp_debug_->history().end());
      return v;
    };
    services.note = [this](const std::string& text) { udp_debug_->note(text); };
  }
  services.led_state = [&dev] {
    const auto t = dev.core().time_ms();
    return web::api::LedStatus{dev.leds().green.on(t), dev.leds().yellow.on(t)};
  };
  services.led = [&dev](std::string_view query) {
    return web::api::led_response(dev.leds(), dev.core().time_ms(), query);
  };
  services.trace = &dev.trace();
  if (dev.personality().code_scripts) services.script = &script_control();
  services.api_token = settings_.api_token;  // --api-token FILE (docs/security.md); "" = off
  router_ = std::make_unique<web::api::Router>(dev, std::move(services));

  web::net::HttpOptions http_options;
  http_options.max_clients = settings_.http_max_clients;
  http_options.ws.max_clients = settings_.ws_max_clients;
  http_options.ids = conn_ids_;
  if (settings_.idle_timeout.count() > 0) {
    http_options.idle_timeout = std::min<std::chrono::milliseconds>(http_options.idle_timeout, settings_.idle_timeout);
  }
  // Drive time is brought up to date before a request reads or changes the drive, and the clock is
  // woken after it (docs/clock.md).
  // A request that arrives while the unit shuts down (the server's last handlers) is not answered
  // from the drive: the bundle may already be gone.
  auto handler = [this, alive = alive_.watch()](const web::api::Request& r, web::api::Respond respond) {
    if (!alive) return respond(web::api::error_page(503, "the drive is shutting down"));
    sync();
    const auto serving = device_->lint().serve(r.conn);  // the lint: this request's writes carry its connection
    router_->handle(r, std::move(respond));
    wake();
  };
  try {
    http_ = std::make_unique<web::net::HttpServer>(io_, tcp::endpoint(address, settings_.http_port), http_options,
                                                   std::move(handler));
  } catch (const boost::system::system_error& e) {
    bind_failed("HTTP", settings_.bind, settings_.http_port, "--http-port", e);
  }
  web::net::HttpObserver observer;
  observer.answered = [this, alive = alive_.watch()](const web::net::HttpObserver::Answer& a) {
    if (!alive) return;
    sync();
    const std::string line =
        a.method.empty() ? std::string("(unreadable request)") : std::string(a.method) + " " + std::string(a.target);
    trace::Flags flags;
    flags.polling = a.polling;  // a page's own polling: the trace view can leave it out (web.md §8.6)
    device_->trace().record(trace::Channel::http, trace::Dir::rx, line, a.conn, a.peer, flags);
    device_->trace().record(trace::Channel::http, trace::Dir::tx, std::to_string(a.status), a.conn, a.peer, flags);
    // morse-led.md §5.1/§5.2: a connection counts for LINK/ACT from its first page request on;
    // page requests flicker the LED, /api/ requests do not.
    if (a.method.empty() || is_api(a.target)) return;
    const auto t = device_->core().time_ms();
    if (lit_http_.insert(a.conn).second) device_->leds().yellow.connection_opened(t);
    device_->leds().yellow.activity(t);
  };
  observer.opened = [this, alive = alive_.watch()](std::uint64_t conn, std::string_view peer) {
    if (!alive) return;
    sync();
    device_->trace().record(trace::Channel::http, trace::Dir::event, "connect", conn, peer);
  };
  observer.closed = [this, alive = alive_.watch()](std::uint64_t conn) {
    if (!alive) return;
    sync();
    device_->trace().record(trace::Channel::http, trace::Dir::event, "disconnect", conn);
    if (lit_http_.erase(conn) == 0) return;
    device_->leds().yellow.connection_closed(device_->core().time_ms());
  };
  http_->set_observer(std::move(observer));
  wire_websocket();
}

// web.md §10: the hub's 50 ms period asks for one status snapshot and one scope block, shared by
// every subscriber; trace events reach it as they are recorded, console messages as produced.
void DriveUnit::wire_websocket() {
  auto& hub = http_->ws_hub();
  web::net::WsSources sources;
  // Like the HTTP handler, the sources never read a bundle that is shutting down or gone.
  sources.info = [this, alive = alive_.watch()] { return alive ? router_->info_text() : std::string("{}"); };
  sources.status = [this, alive = alive_.watch()] {
    if (!alive) return std::string();
    sync();
    return router_->status_message();
  };
  sources.scope = [this, alive = alive_.watch()] {
    if (!alive) return std::string();
    sync();
    auto block = device_->scope().take_new();
    return block.samples.empty() ? std::string() : device::scope_message(block);
  };
  sources.trace_message = [](std::span<const trace::Event> events, trace::ChannelSet) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : events) list.push_back(web::api::event_json(e));
    return nlohmann::json{{"type", "trace"}, {"events", std::move(list)}}.dump(
        -1, ' ', false, nlohmann::json::error_handler_t::replace);
  };
  hub.set_sources(std::move(sources));
  device_->trace().set_listener([&hub](const trace::Event& e) { hub.on_trace(e); });
  if (udp_debug_) udp_debug_->set_message_listener([&hub](const std::string& text) { hub.publish_udp(text); });
}

}  // namespace mcemu::server
