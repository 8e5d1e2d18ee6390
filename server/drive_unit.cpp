#include "server/drive_unit.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/steady_timer.hpp>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "persistence/atomic_file.hpp"
#include "persistence/state_dir.hpp"
#include "persistence/worker_storage.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/line/net/pty_server.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "scripting/engine.hpp"
#include "server/clock_driver.hpp"
#include "trace/trace.hpp"
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

}  // namespace

std::string utc_iso8601() { return utc_format("%Y-%m-%dT%H:%M:%SZ"); }

std::int64_t unix_ms_now() {
  const auto since_epoch = std::chrono::system_clock::now().time_since_epoch();
  return std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch).count();
}

// Every UDP line is stamped with this: arithmetic formatting (trace::format_utc_ms), no gmtime
// or strftime per call (they were 4.6 % of mcemu's CPU under a RefGo TP loop, perf).
std::string utc_iso8601_ms() { return trace::format_utc_ms(unix_ms_now()); }

[[noreturn]] void bind_failed(const std::string& service, const std::string& bind, std::uint16_t port,
                              const std::string& flag, const boost::system::system_error& e) {
  throw StartupError("cannot listen on " + bind + ":" + std::to_string(port) + " for " + service + " (" +
                     e.code().message() + "); choose another port with " + flag);
}
std::string utc_compact() { return utc_format("%Y%m%dT%H%M%SZ"); }

DriveUnit::DriveUnit(asio::io_context& io, Settings settings, int number, std::string log_prefix)
    : io_(io), settings_(std::move(settings)), number_(number), log_prefix_(std::move(log_prefix)) {
  state_dir_ = std::make_unique<persistence::StateDir>(settings_.state_dir, number_);
  state_dir_->remove_stale_temp();
  storage_ = std::make_unique<persistence::WorkerStorage>(io_, state_dir_->state_file(),
                                                          persistence::write_options_from_environment());
  device::Setup setup;
  setup.model = settings_.model;
  setup.config = settings_.config;
  if (settings_.ip_explicit) setup.explicit_ip = parse_ipv4(settings_.ip, "--ip");
  setup.mcemu_version = MCEMU_VERSION;
  setup.lint_mode = settings_.lint_mode;
  setup.manual_clock = settings_.clock.kind == sim::ClockMode::Kind::manual;
  device_ = std::make_unique<device::Device>(std::move(setup), environment());
  device::Observers observers;
  observers.powering_down = [this] { script_power_down(); };
  observers.powered_up = [this] { script_power_up(); };
  observers.factory_reset = [this] {
    if (engine_) engine_->factory_reset();
  };
  observers.settings_changed = [this](const device::RuntimeSettings& s) {
    if (udp_debug_) udp_debug_->set_notes(s.udp_emulator_notes);
    apply_script_settings(s);
  };
  device_->set_observers(std::move(observers));
  bind_listeners();
  if (device_->personality().code_scripts) build_script();
}

DriveUnit::~DriveUnit() { shutdown(); }

// What the bundle takes from the shell: the state directory (load at start-up, the worker that
// writes it), the wall clock, the log and the clock's wake.
device::Environment DriveUnit::environment() {
  device::Environment env;
  env.storage = storage_.get();
  env.load_state = [this](od::ObjectDictionary& od, const std::string& model) -> std::optional<persistence::Image> {
    auto loaded = state_dir_->load(model, od, utc_compact());
    if (!loaded) return std::nullopt;
    std::vector<std::string> ignored = loaded->bad_keys;
    for (const auto& issue : od.load_values(loaded->image.objects)) {
      ignored.push_back(persistence::object_key(issue.index, issue.sub));
    }
    state_dir_->warn_ignored(ignored);
    return loaded->image;
  };
  env.stored_plant_position = [this](const std::string& model) { return state_dir_->load_plant(model); };
  env.unix_ms = unix_ms_now;
  env.now_utc = utc_iso8601;
  env.log = [this](device::LogLevel level, const std::string& text) {
    switch (level) {
      case device::LogLevel::debug: spdlog::debug("{}{}", log_prefix_, text); break;
      case device::LogLevel::info: spdlog::info("{}{}", log_prefix_, text); break;
      case device::LogLevel::warning: spdlog::warn("{}{}", log_prefix_, text); break;
      case device::LogLevel::error: spdlog::error("{}{}", log_prefix_, text); break;
    }
  };
  env.wake = [this] { wake(); };
  env.note = [this](const std::string& text) { note(text); };
  // The drive's own files beside drive-k.json (MC BASIC): "faulhaber/…" is the spec's folder for
  // drive 1 and "faulhaber-k/…" for drive k of a fleet (docs/faulhaber.md).
  const auto own_path = [this](const std::string& name) {
    std::string n = name;
    if (number_ > 1 && n.rfind("faulhaber/", 0) == 0) n.replace(0, 9, "faulhaber-" + std::to_string(number_));
    return state_dir_->dir() / n;
  };
  env.read_state_file = [own_path](const std::string& name) -> std::optional<std::string> {
    std::error_code ec;
    const auto path = own_path(name);
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in && !in.eof()) return std::nullopt;
    return text.str();
  };
  env.write_state_file = [this, own_path](const std::string& name, std::string contents) {
    storage_->write_file(own_path(name), std::move(contents),
                         [prefix = log_prefix_, name](std::optional<std::string> error) {
                           if (error) spdlog::error("{}cannot write {}: {}", prefix, name, *error);
                         });
  };
  return env;
}

void DriveUnit::note(const std::string& text) {
  if (udp_debug_) udp_debug_->note(text);
}

// drive-1.plant.json at clean shutdown (persistence.md §8), with the atomic procedure of §10.
void DriveUnit::write_plant_state() const {
  const auto text = persistence::serialize_plant(device_->preset().name, device_->core().raw_position_inc());
  if (auto error = persistence::write_atomically(state_dir_->plant_file(), text)) {
    spdlog::error("cannot write the plant state: {}", *error);
  }
}

// Only this drive's next step is made full: the fleet's other drives stay quiet.
void DriveUnit::sync() {
  if (clock_) clock_->sync(&device_->steps());
}

void DriveUnit::wake() {
  if (clock_) {
    clock_->wake(&device_->steps());
  } else if (device_) {
    device_->steps().touch();
  }
}

void DriveUnit::settle() {
  if (clock_) clock_->settle(&device_->steps());
}

DriveUnit::Ports DriveUnit::ports() const {
  Ports p;
  if (refgo_) p.refgo = refgo_->port();
  if (slcan_) p.slcan = slcan_->port();
  if (http_) p.http = http_->port();
  if (udp_) p.udp = udp_->local_endpoint().port();
  return p;
}

void DriveUnit::start() {
  const auto log_listen = [&](const char* name, const char* proto, std::uint16_t port) {
    spdlog::info("{}listening: {} {} {}:{}", log_prefix_, name, proto, settings_.bind, port);
  };
  if (refgo_) log_listen("refgo", "tcp", refgo_->port());
  if (slcan_) log_listen("slcan", "tcp", slcan_->port());
  if (faulhaber_) log_listen("faulhaber", "tcp", faulhaber_->port());
  if (faulhaber_pty_) {
    spdlog::info("{}listening: faulhaber pty {} -> {}", log_prefix_, faulhaber_pty_->link_path(),
                 faulhaber_pty_->subordinate());
  }
  log_listen("http", "tcp", http_->port());
  if (udp_) log_listen("udp", "udp", udp_->local_endpoint().port());
  if (!device_->active_ip().empty()) {
    spdlog::info("{}drive IP address {} / {}", log_prefix_, device_->active_ip(), device_->active_mask());
  }
  if (refgo_) refgo_->start();
  if (slcan_) slcan_->start();
  if (faulhaber_) faulhaber_->start();
  if (faulhaber_pty_) faulhaber_pty_->start();
  http_->start();
  if (udp_debug_) {
    udp_debug_->power_up(device_->active_ip(), device_->script_id());
    udp_debug_->start();
  }
  device_->power_up_network();
  script_power_up();
}

// persistence.md §7, in its order: the core powers down (plant position kept and written) and the
// script engine is terminated, the RefGo and SLCAN connections are closed, the UDP listeners and
// backlog forgotten, the RAM image rebuilt from the file as it is now, the UDP start-up block
// produced again, the node boots, the script starts if the stored autostart flag is set. The HTTP
// server and its connections stay (the request that asked for it gets its answer). A Store still
// being written finishes first.
void DriveUnit::power_cycle(std::function<void()> done) {
  if (device_->persistence().in_flight() > 0) {
    auto timer = std::make_shared<asio::steady_timer>(io_, std::chrono::milliseconds(5));
    timer->async_wait(
        [this, timer, alive = alive_.watch(), done = std::move(done)](const boost::system::error_code& ec) mutable {
          if (!ec && alive) power_cycle(std::move(done));
        });
    return;
  }
  sync();
  spdlog::info("{}power cycle", log_prefix_);
  write_plant_state();
  script_power_down();
  if (refgo_) refgo_->close_connections();
  if (slcan_) slcan_->close_connections();
  device_->power_cycle();
  if (udp_debug_) udp_debug_->power_cycle(device_->active_ip(), device_->script_id());
  device_->power_up_network();
  device_->handle_events();
  script_power_up();
  done();
}

void DriveUnit::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  alive_.end();
  engine_.reset();  // kills a running script's process group
  // The WebSocket hub goes with the HTTP server, before the bundle (members are destroyed in
  // reverse order): nothing the bundle records from now on may reach it.
  if (device_) device_->trace().set_listener({});
  if (udp_debug_) udp_debug_->set_message_listener({});
  if (refgo_) refgo_->stop();
  if (slcan_) slcan_->stop();
  if (faulhaber_) faulhaber_->stop();
  if (faulhaber_pty_) faulhaber_pty_->stop();
  if (http_) http_->stop();
  if (udp_debug_) udp_debug_->stop();
  if (udp_) {
    boost::system::error_code ec;
    udp_->close(ec);
  }
  if (storage_) storage_->drain();
  if (device_) write_plant_state();
}

}  // namespace mcemu::server
