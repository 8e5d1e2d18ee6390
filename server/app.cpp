#include "server/app.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <boost/asio/ip/address.hpp>
#include <ctime>

#include "persistence/service.hpp"
#include "persistence/state_dir.hpp"
#include "persistence/worker_storage.hpp"
#include "protocols/line/net/line_server.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_image.hpp"
#include "web/api/router.hpp"
#include "web/net/http_server.hpp"

namespace mcemu::server {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using udp = asio::ip::udp;

namespace {

std::string utc_format(const char* fmt) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::array<char, 32> buf{};
  std::strftime(buf.data(), buf.size(), fmt, &tm);
  return buf.data();
}

// Turns a bind failure into the one start-up line of the spec README.
[[noreturn]] void bind_failed(const std::string& service, const std::string& bind, std::uint16_t port,
                              const std::string& flag, const boost::system::system_error& e) {
  throw StartupError("cannot listen on " + bind + ":" + std::to_string(port) + " for " + service + " (" +
                     e.code().message() + "); choose another port with " + flag);
}

// Placeholder session for the RefGo and SLCAN ports until their protocol engines are wired: the
// listener, its limits and socket options exist from the foundation on (issue 2).
class SilentSession final : public line::StreamSession {
 public:
  void receive(std::string_view) override {}
  std::string take_output() override { return {}; }
  void peer_closed() override { done_ = true; }
  bool finished() const override { return done_; }

 private:
  bool done_ = false;
};

}  // namespace

std::string utc_iso8601() { return utc_format("%Y-%m-%dT%H:%M:%SZ"); }
std::string utc_compact() { return utc_format("%Y%m%dT%H%M%SZ"); }

App::App(asio::io_context& io, Settings settings) : io_(io), settings_(std::move(settings)) {
  build_drive();
  bind_listeners();
}

App::~App() { shutdown(); }

void App::build_drive() {
  preset_ = make_preset(settings_);
  od_ = std::make_unique<od::ObjectDictionary>(preset_);
  apply_config_objects(*od_, settings_.config);
  persistence::Image factory = persistence::snapshot(*od_);

  spdlog::info("model {}: {} {}, XDD {}, {} controller, 6502h = 0x{:02X}", preset_.name, preset_.identity.device_name,
               preset_.identity.software_version, preset_.xdd_file, preset_.is_rabbit() ? "RABBIT" : "standard",
               preset_.supported_modes);

  state_dir_ = std::make_unique<persistence::StateDir>(settings_.state_dir);
  state_dir_->remove_stale_temp();
  auto loaded = state_dir_->load(preset_.name, *od_, utc_compact());
  std::optional<persistence::Image> on_file;
  if (loaded) {
    std::vector<std::string> ignored = loaded->bad_keys;
    for (const auto& issue : od_->load_values(loaded->image.objects)) {
      ignored.push_back(persistence::object_key(issue.index, issue.sub));
    }
    state_dir_->warn_ignored(ignored);
    on_file = loaded->image;
  }

  // The active IP address: --ip given explicitly > stored 5007h > factory (persistence.md §6).
  if (settings_.ip_explicit) {
    const auto octets = parse_ipv4(settings_.ip, "--ip");
    const std::string stored = active_ip();
    std::vector<od::StoredValue> ip;
    for (std::uint8_t s = 1; s <= 4; ++s) ip.push_back({0x5007, s, od::Value{std::int64_t{octets[s - 1]}}});
    od_->load_values(ip);
    if (on_file && stored != settings_.ip) {
      spdlog::info("--ip {} overrides the stored address {}", settings_.ip, stored);
    }
  }

  storage_ = std::make_unique<persistence::WorkerStorage>(io_, state_dir_->state_file(),
                                                          persistence::write_options_from_environment());
  persistence::ServiceHooks hooks;
  hooks.now_utc = utc_iso8601;
  persistence_ = std::make_unique<persistence::Service>(*od_, preset_.name, MCEMU_VERSION, std::move(factory),
                                                        std::move(on_file), *storage_, std::move(hooks));
}

std::string App::active_ip() const {
  std::string out;
  for (std::uint8_t s = 1; s <= 4; ++s) out += (s > 1 ? "." : "") + std::to_string(od_->number(0x5007, s));
  return out;
}

std::string App::active_mask() const {
  std::string out;
  for (std::uint8_t s = 1; s <= 4; ++s) out += (s > 1 ? "." : "") + std::to_string(od_->number(0x5008, s));
  return out;
}

void App::bind_listeners() {
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

  web::net::HttpOptions http_options;
  http_options.max_clients = settings_.http_max_clients;
  auto router = std::make_shared<web::api::Router>(
      *od_,
      [this] {
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
      },
      [this](std::uint16_t index, std::uint8_t sub) -> std::optional<od::Value> {
        for (const auto& sv : persistence_->factory().objects) {
          if (sv.index == index && sv.sub == sub) return sv.value;
        }
        return std::nullopt;
      });
  try {
    http_ = std::make_unique<web::net::HttpServer>(
        io_, tcp::endpoint(address, settings_.http_port), http_options,
        [router](const web::api::Request& r, web::api::Respond respond) { router->handle(r, std::move(respond)); });
  } catch (const boost::system::system_error& e) {
    bind_failed("HTTP", settings_.bind, settings_.http_port, "--http-port", e);
  }
  try {
    udp_ = std::make_unique<udp::socket>(io_);
    udp_->open(address.is_v6() ? udp::v6() : udp::v4());
    udp_->bind(udp::endpoint(address, settings_.udp_port));
  } catch (const boost::system::system_error& e) {
    bind_failed("UDP debug output", settings_.bind, settings_.udp_port, "--udp-port", e);
  }
}

// ---- protocol engines behind the listeners ----------------------------------------------------

std::unique_ptr<line::StreamSession> App::make_refgo_session(const line::net::PeerInfo&) {
  return std::make_unique<SilentSession>();
}

std::unique_ptr<line::StreamSession> App::make_slcan_session(const line::net::PeerInfo&) {
  return std::make_unique<SilentSession>();
}

// One simulation step of 1 ms (drive-core.md §2), called by the clock driver.
void App::step() {}

void App::start_udp_receive() {
  udp_->async_receive_from(asio::buffer(udp_buffer_), udp_peer_,
                           [this](const boost::system::error_code& ec, std::size_t) {
                             if (ec == asio::error::operation_aborted || shut_down_) return;
                             start_udp_receive();
                           });
}

void App::start() {
  const auto log_listen = [&](const char* name, const char* proto, std::uint16_t port) {
    spdlog::info("listening: {} {} {}:{}", name, proto, settings_.bind, port);
  };
  log_listen("refgo", "tcp", refgo_->port());
  log_listen("slcan", "tcp", slcan_->port());
  log_listen("http", "tcp", http_->port());
  log_listen("udp", "udp", udp_->local_endpoint().port());
  spdlog::info("drive IP address {} / {}", active_ip(), active_mask());
  refgo_->start();
  slcan_->start();
  http_->start();
  start_udp_receive();
  clock_ = std::make_unique<ClockDriver>(io_, [this] { step(); });
  clock_->start();
  spdlog::info("mcemu {} ready", MCEMU_VERSION);
}

void App::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  if (clock_) clock_->stop();
  if (refgo_) refgo_->stop();
  if (slcan_) slcan_->stop();
  if (http_) http_->stop();
  if (udp_) {
    boost::system::error_code ec;
    udp_->close(ec);
  }
  if (storage_) storage_->drain();
}

}  // namespace mcemu::server
