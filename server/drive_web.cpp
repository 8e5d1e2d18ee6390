// DriveUnit, the web side (web.md): the JSON API's services, the HTTP server with its observer
// (trace channel http, the LINK/ACT LED of page connections) and the WebSocket hub's sources.
#include <spdlog/spdlog.h>

#include <algorithm>

#include "persistence/service.hpp"
#include "protocols/canopen/eds.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_image.hpp"
#include "server/drive_unit.hpp"
#include "trace/trace.hpp"
#include "web/api/led_view.hpp"
#include "web/api/router.hpp"
#include "web/api/scope.hpp"
#include "web/api/trace_export.hpp"
#include "web/net/http_server.hpp"

namespace mcemu::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

namespace {

// The start values of the runtime settings (web.md §8.9): defaults, then "settings" of --config.
web::api::RuntimeSettings runtime_settings(const nlohmann::json& config) {
  web::api::RuntimeSettings s;
  const auto it = config.find("settings");
  if (it == config.end()) return s;
  if (auto error = web::api::apply_settings(s, *it)) throw UsageError("invalid \"settings\" in --config: " + *error);
  return s;
}

bool is_api(std::string_view target) { return target.rfind("/api/", 0) == 0; }

}  // namespace

void DriveUnit::build_web(const asio::ip::address& address) {
  trace_ = std::make_unique<trace::Ring>(trace::Ring::Clocks{[this] { return core_->time_ms(); }, unix_ms_now});
  web::api::Services services;
  services.info = [this] {
    web::api::Info i;
    i.version = MCEMU_VERSION;
    i.model = preset_.name;
    i.display_name = preset_.identity.display_name;
    i.device_name = preset_.identity.device_name;
    i.software_version = preset_.identity.software_version;
    i.serial = static_cast<std::uint32_t>(od_->number(0x3404, 4));
    i.ip = active_ip();
    i.mask = active_mask();
    i.bind = settings_.bind;
    i.refgo_port = refgo_->port();
    i.slcan_port = slcan_->port();
    i.http_port = http_->port();
    i.udp_port = udp_->local_endpoint().port();
    i.state_dir = settings_.state_dir;
    return i;
  };
  services.factory = [this](std::uint16_t index, std::uint8_t sub) -> std::optional<od::Value> {
    for (const auto& sv : persistence_->factory().objects) {
      if (sv.index == index && sv.sub == sub) return sv.value;
    }
    return std::nullopt;
  };
  services.eds = [this] {
    od::ObjectDictionary factory_od(preset_);
    factory_od.load_values(persistence_->factory().objects);
    return canopen::make_eds(factory_od, eds_info(preset_));
  };
  services.clock = [this] {
    web::api::ClockInfo c;
    if (clock_) {
      c.mode = clock_->mode().kind == ClockMode::Kind::real     ? "real"
               : clock_->mode().kind == ClockMode::Kind::scaled ? "scaled"
                                                                : "manual";
      c.scale = clock_->mode().kind == ClockMode::Kind::manual ? 0.0 : clock_->scale();
    }
    return c;
  };
  services.advance_clock = [this](std::uint64_t ms, std::function<void(std::uint64_t)> done) {
    if (!clock_ || !clock_->advance(ms, [this, done] { done(core_->time_ms()); })) done(core_->time_ms());
  };
  services.power_cycle = [this](std::function<void()> done) { power_cycle(std::move(done)); };
  services.refgo_clients = [this] { return static_cast<int>(refgo_->connection_count()); };
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
  services.led_state = [this] {
    const auto t = core_->time_ms();
    return web::api::LedStatus{leds_.green.on(t), leds_.yellow.on(t)};
  };
  services.led = [this](std::string_view query) { return web::api::led_response(leds_, core_->time_ms(), query); };
  services.settings = runtime_settings(settings_.config);
  services.settings_changed = [this](const web::api::RuntimeSettings& s) {
    udp_debug_->set_notes(s.udp_emulator_notes);
    apply_script_settings(s.script_strict, s.script_memory_mib, s.trace_script_calls);
  };
  services.trace = trace_.get();
  services.script = &script_control();
  services.api_token = settings_.api_token;  // --api-token FILE (docs/security.md); "" = off
  router_ = std::make_shared<web::api::Router>(web::api::Drive{*od_, *core_, *refgo_interpreter_, preset_},
                                               std::move(services));

  web::net::HttpOptions http_options;
  http_options.max_clients = settings_.http_max_clients;
  if (settings_.idle_timeout.count() > 0) {
    http_options.idle_timeout = std::min<std::chrono::milliseconds>(http_options.idle_timeout, settings_.idle_timeout);
  }
  // Drive time is brought up to date before a request reads or changes the drive, and the clock is
  // woken after it (docs/clock.md).
  auto handler = [this, router = router_, alive = std::weak_ptr<DriveUnit*>(self_)](const web::api::Request& r,
                                                                                    web::api::Respond respond) {
    if (!alive.lock()) return router->handle(r, std::move(respond));
    sync();
    router->handle(r, std::move(respond));
    wake();
  };
  try {
    http_ = std::make_unique<web::net::HttpServer>(io_, tcp::endpoint(address, settings_.http_port), http_options,
                                                   std::move(handler));
  } catch (const boost::system::system_error& e) {
    bind_failed("HTTP", settings_.bind, settings_.http_port, "--http-port", e);
  }
  web::net::HttpObserver observer;
  observer.answered = [this, alive = std::weak_ptr<DriveUnit*>(self_)](const web::net::HttpObserver::Answer& a) {
    if (!alive.lock()) return;
    sync();
    const std::string line =
        a.method.empty() ? std::string("(unreadable request)") : std::string(a.method) + " " + std::string(a.target);
    trace_->record(trace::Channel::http, trace::Dir::rx, line, a.conn, a.peer);
    trace_->record(trace::Channel::http, trace::Dir::tx, std::to_string(a.status), a.conn, a.peer);
    // morse-led.md §5.1/§5.2: a connection counts for LINK/ACT from its first page request on;
    // page requests flicker the LED, /api/ requests do not.
    if (a.method.empty() || is_api(a.target)) return;
    const auto t = core_->time_ms();
    if (lit_http_.insert(a.conn).second) leds_.yellow.connection_opened(t);
    leds_.yellow.activity(t);
  };
  observer.opened = [this, alive = std::weak_ptr<DriveUnit*>(self_)](std::uint64_t conn, std::string_view peer) {
    if (!alive.lock()) return;
    sync();
    trace_->record(trace::Channel::http, trace::Dir::event, "connect", conn, peer);
  };
  observer.closed = [this, alive = std::weak_ptr<DriveUnit*>(self_)](std::uint64_t conn) {
    if (!alive.lock()) return;
    sync();
    trace_->record(trace::Channel::http, trace::Dir::event, "disconnect", conn);
    if (lit_http_.erase(conn) == 0) return;
    leds_.yellow.connection_closed(core_->time_ms());
  };
  http_->set_observer(std::move(observer));
  wire_websocket();
}

// web.md §10: the hub's 50 ms period asks for one status snapshot and one scope block, shared by
// every subscriber; trace events reach it as they are recorded, console messages as produced.
void DriveUnit::wire_websocket() {
  auto& hub = http_->ws_hub();
  web::net::WsSources sources;
  sources.info = [this] { return router_->info_text(); };
  sources.status = [this] {
    sync();
    return router_->status_message();
  };
  sources.scope = [this] {
    sync();
    auto block = router_->scope().take_new();
    return block.samples.empty() ? std::string() : web::api::scope_message(block);
  };
  sources.trace_message = [](std::span<const trace::Event> events, trace::ChannelSet) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : events) list.push_back(web::api::event_json(e));
    return nlohmann::json{{"type", "trace"}, {"events", std::move(list)}}.dump(
        -1, ' ', false, nlohmann::json::error_handler_t::replace);
  };
  hub.set_sources(std::move(sources));
  trace_->set_listener([&hub](const trace::Event& e) { hub.on_trace(e); });
  udp_debug_->set_message_listener([&hub](const std::string& text) { hub.publish_udp(text); });
}

}  // namespace mcemu::server
