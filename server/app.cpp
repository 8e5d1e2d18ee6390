#include "server/app.hpp"

#include <spdlog/spdlog.h>

#include <array>
#include <boost/asio/ip/address.hpp>
#include <ctime>

#include "drive/od/model_tables.hpp"
#include "iofunc/io_functions.hpp"
#include "persistence/atomic_file.hpp"
#include "persistence/service.hpp"
#include "persistence/state_dir.hpp"
#include "persistence/worker_storage.hpp"
#include "protocols/canopen/comm_reload.hpp"
#include "protocols/canopen/dynamic_mapping.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/session.hpp"
#include "protocols/udp_debug/messages.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "server/canopen_bus.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_image.hpp"
#include "server/plant_settings.hpp"
#include "web/api/faults.hpp"
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

// Wraps a session to report the client's connect and disconnect as UDP emulator notes
// (udp-debug.md §4.7); the session's behaviour is unchanged.
class NotedSession final : public line::StreamSession {
 public:
  NotedSession(std::unique_ptr<line::StreamSession> inner, std::weak_ptr<udp_debug::net::UdpDebugService> udp,
               std::string what)
      : inner_(std::move(inner)), udp_(std::move(udp)), what_(std::move(what)) {
    inner_->set_wake([this] { wake(); });
    note(" connected");
  }
  // A connection's last handler may run after the App is gone; then there is nobody to tell.
  ~NotedSession() override { note(" disconnected"); }
  NotedSession(const NotedSession&) = delete;
  NotedSession& operator=(const NotedSession&) = delete;

  void receive(std::string_view bytes) override { inner_->receive(bytes); }
  std::string take_output() override { return inner_->take_output(); }
  void peer_closed() override { inner_->peer_closed(); }
  bool finished() const override { return inner_->finished(); }
  bool paused() const override { return inner_->paused(); }

 private:
  void note(const char* event) const {
    if (auto udp = udp_.lock()) udp->note(what_ + event);
  }

  std::unique_ptr<line::StreamSession> inner_;
  std::weak_ptr<udp_debug::net::UdpDebugService> udp_;
  std::string what_;
};

bool udp_notes_setting(const nlohmann::json& config) {
  const auto s = config.find("settings");
  if (s == config.end() || !s->is_object()) return false;
  const auto n = s->find("udpEmulatorNotes");
  if (n == s->end()) return false;
  if (!n->is_boolean())
    throw UsageError("invalid value for settings.udpEmulatorNotes in --config (expected true/false)");
  return n->get<bool>();
}

}  // namespace

std::string utc_iso8601() { return utc_format("%Y-%m-%dT%H:%M:%SZ"); }
std::string utc_compact() { return utc_format("%Y%m%dT%H%M%SZ"); }

App::App(asio::io_context& io, Settings settings) : io_(io), settings_(std::move(settings)) {
  parse_canopen_config();
  build_drive();
  build_canopen();
  bind_listeners();
}

App::~App() { shutdown(); }

void App::build_drive() {
  preset_ = make_preset(settings_);
  if (canopen_config_.dynamic_pdo_mapping) {  // slcan-canopen.md §9.7: rw mapping objects
    auto entries = od::build_entries(preset_);
    canopen::make_mapping_dynamic(entries);
    od_ = std::make_unique<od::ObjectDictionary>(std::move(entries));
  } else {
    od_ = std::make_unique<od::ObjectDictionary>(preset_);
  }
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

  const std::string stored_ip = active_ip();
  apply_explicit_ip();
  if (settings_.ip_explicit && on_file && stored_ip != settings_.ip) {
    spdlog::info("--ip {} overrides the stored address {}", settings_.ip, stored_ip);
  }

  try {
    core_ = std::make_unique<core::DriveCore>(preset_, *od_, plant_config_from_json(settings_.config));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("invalid plant configuration in --config: ") + e.what());
  }
  // The I/O functions wrap the core: they step it and power it on (iofunc.md §3).
  iofunc_ = std::make_unique<iofunc::IoFunctions>(*od_, *core_);

  storage_ = std::make_unique<persistence::WorkerStorage>(io_, state_dir_->state_file(),
                                                          persistence::write_options_from_environment());
  persistence::ServiceHooks hooks;
  hooks.now_utc = utc_iso8601;
  hooks.operation_enabled = [this] { return core_->state() == core::PdsState::operation_enabled; };
  hooks.home_offset_inc = [this] { return core_->home_offset_inc(); };
  hooks.after_restore = [this] {
    iofunc_->after_bulk_load();
    if (canopen_) canopen_->node().reload();
  };
  persistence_ = std::make_unique<persistence::Service>(*od_, preset_.name, MCEMU_VERSION, std::move(factory),
                                                        std::move(on_file), *storage_, std::move(hooks));
  refgo_interpreter_ = std::make_unique<refgo::Interpreter>(*od_, *core_);
  iofunc_->power_on(stored_power_on_state());
}

// What a power on takes from outside the OD (persistence.md §2, §8): the plant position of the last
// clean shutdown (else the preset's power-on position) and the stored home offset, which the core
// applies only on absolute-encoder models.
core::PowerOnState App::stored_power_on_state() const {
  core::PowerOnState s;
  s.raw_position_inc = state_dir_->load_plant(preset_.name);
  if (const auto& file = persistence_->on_file()) s.home_offset_inc = file->home_offset_inc;
  return s;
}

// drive-1.plant.json at clean shutdown (persistence.md §8), with the atomic procedure of §10.
void App::write_plant_state() const {
  const auto text = persistence::serialize_plant(preset_.name, core_->raw_position_inc());
  if (auto error = persistence::write_atomically(state_dir_->plant_file(), text)) {
    spdlog::error("cannot write the plant state: {}", *error);
  }
}

// The active IP address: --ip given explicitly > stored 5007h > factory (persistence.md §6).
void App::apply_explicit_ip() {
  if (!settings_.ip_explicit) return;
  const auto octets = parse_ipv4(settings_.ip, "--ip");
  std::vector<od::StoredValue> ip;
  for (std::uint8_t s = 1; s <= 4; ++s) ip.push_back({0x5007, s, od::Value{std::int64_t{octets[s - 1]}}});
  od_->load_values(ip);
}

// The four octets of 5007h (IP address) or 5008h (mask) as "A.B.C.D".
std::string App::dotted_quad(std::uint16_t index) const {
  std::string out;
  for (std::uint8_t s = 1; s <= 4; ++s) {
    if (s > 1) out += '.';
    out += std::to_string(od_->number(index, s));
  }
  return out;
}

std::string App::active_ip() const { return dotted_quad(0x5007); }
std::string App::active_mask() const { return dotted_quad(0x5008); }

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

  faults_ = std::make_unique<web::api::FaultInjections>(*core_);
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
      },
      faults_.get());
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
    // SO_REUSEADDR lets a host tool such as Fullmo's UdpMonitor bind the same port (udp-debug.md §1.2).
    udp_->set_option(udp::socket::reuse_address(true));
    udp_->bind(udp::endpoint(address, settings_.udp_port));
  } catch (const boost::system::system_error& e) {
    bind_failed("UDP debug output", settings_.bind, settings_.udp_port, "--udp-port", e);
  }
  udp_debug_ = std::make_shared<udp_debug::net::UdpDebugService>(io_, *udp_);
  udp_debug_->set_notes(udp_notes_setting(settings_.config));
}

// ---- protocol engines behind the listeners ----------------------------------------------------

std::unique_ptr<line::StreamSession> App::make_refgo_session(const line::net::PeerInfo& peer) {
  auto session = std::make_unique<refgo::Session>(*refgo_interpreter_);
  if (!udp_debug_->notes()) return session;
  return std::make_unique<NotedSession>(std::move(session), udp_debug_, "refgo client " + peer.address);
}

std::unique_ptr<line::StreamSession> App::make_slcan_session(const line::net::PeerInfo&) {
  return canopen_->make_session();
}

// One simulation step of 1 ms (drive-core.md §2), called by the clock driver; the RefGo programs
// (jog timer, Back & Forth) follow in the same drive time, then the CANopen node (its TPDOs see
// this step's values, its EMCYs come from this step's events).
void App::step() {
  iofunc_->step();
  faults_->on_step();
  refgo_interpreter_->on_step();
  on_core_events();
  canopen_->step();
}

void App::on_core_events() {
  for (const auto& d : iofunc_->drain_diagnostics()) {
    if (d.level == core::DiagnosticLevel::warning) {
      spdlog::warn("I/O function: {}", d.text);
    } else {
      spdlog::debug("I/O function: {}", d.text);
    }
  }
  for (const auto& e : core_->drain_events()) {
    if (const auto* emcy = std::get_if<core::Emcy>(&e)) {
      if (canopen_) canopen_->node().emit_emcy(emcy->code, emcy->reg, emcy->data);
    } else if (const auto* f = std::get_if<core::FaultRaised>(&e)) {
      udp_debug_->note(udp_debug::fault_text(f->code));
    } else if (std::holds_alternative<core::FaultResetDone>(e)) {
      udp_debug_->note("fault cleared");
    }
  }
}

// ---- CANopen node on the SLCAN port (slcan-canopen.md) ----------------------------------------

void App::parse_canopen_config() {
  try {
    slcan_config_ = slcan::slcan_config_from_json(settings_.config.value("slcan", nlohmann::json::object()));
    canopen_config_ = canopen::canopen_config_from_json(settings_.config.value("canopen", nlohmann::json::object()));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("config: ") + e.what());
  }
}

void App::build_canopen() {
  canopen::Node::Hooks hooks;
  hooks.reset_node = [this] {  // the drive part of a power cycle (persistence.md §7)
    core::PowerOnState keep{core_->raw_position_inc(), core_->home_offset_inc()};
    if (const auto& file = persistence_->on_file()) keep.home_offset_inc = file->home_offset_inc;
    rebuild_ram_image();
    iofunc_->power_on(keep);  // the core's power_on() and iofunc's volatile state
    on_core_events();
  };
  hooks.reset_communication = [this] { reload_communication_objects(); };
  hooks.connection_lost = [this] {  // life guarding expired (slcan-canopen.md §5.2)
    core_->connection_lost();
    on_core_events();
  };
  // EMCYs raised by an SDO/RPDO write go out after that write's SDO response (§2 ordering)
  hooks.after_od_write = [this] { on_core_events(); };
  hooks.diagnostic = [](const std::string& text) { spdlog::debug("canopen: {}", text); };
  canopen_ = std::make_unique<CanopenBus>(*od_, slcan_config_, canopen_config_, std::move(hooks));
}

// NMT reset node: the drive part of a power cycle (persistence.md §5, §7): RAM image = factory
// image (preset, then --config "objects") overlaid with the file as it is on disk now, then an
// explicit --ip. Live values, constants and command entries are the core's and the OD's own.
void App::rebuild_ram_image() {
  std::vector<od::StoredValue> image;
  od_->for_each([&](const od::EntryInfo& e, const od::Value&) {
    if (e.cls == od::EntryClass::param || e.cls == od::EntryClass::comm || e.cls == od::EntryClass::proc) {
      image.push_back({e.index, e.sub, e.factory});
    }
  });
  od_->load_values(image);
  apply_config_objects(*od_, settings_.config);
  if (const auto& file = persistence_->on_file()) od_->load_values(file->objects);
  apply_explicit_ip();
  spdlog::info("canopen: NMT reset node: drive image rebuilt from the factory image and the state file");
}

// NMT reset communication: 1000h–1FFFh and 3404h.03 from the factory image and the file.
void App::reload_communication_objects() {
  const auto& file = persistence_->on_file();
  canopen::reload_communication_objects(
      *od_, persistence_->factory().objects,
      file ? std::span<const od::StoredValue>(file->objects) : std::span<const od::StoredValue>());
}

// The UDP debug console starts with the start-up block of this power-up (udp-debug.md §4.1).
void App::start_udp_receive() {
  udp_debug_->power_up(active_ip(), script_id());
  udp_debug_->start();
}

std::string App::script_id() const {
  const auto id = od_->read(0x3500, 1);
  if (id && std::holds_alternative<std::string>(*id) && !std::get<std::string>(*id).empty()) {
    return std::get<std::string>(*id);
  }
  return "(empty)";
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
  // Run the drive to the CANopen node's boot-up before the loop serves any connection
  // (docs/decisions/0004): "ready" means the node answers. After the UDP power-up block, so that
  // notes of these first steps follow it.
  canopen_->power_on();
  for (int i = 0; i < 1000 && canopen_->node().state() == canopen::NmtState::initialising; ++i) step();
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
  if (udp_debug_) udp_debug_->stop();
  if (udp_) {
    boost::system::error_code ec;
    udp_->close(ec);
  }
  if (storage_) storage_->drain();
  if (core_) write_plant_state();
}

}  // namespace mcemu::server
