#include "server/drive_unit.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/steady_timer.hpp>
#include <ctime>

#include "drive/od/model_tables.hpp"
#include "iofunc/io_functions.hpp"
#include "persistence/atomic_file.hpp"
#include "persistence/service.hpp"
#include "persistence/state_dir.hpp"
#include "persistence/worker_storage.hpp"
#include "protocols/canopen/comm_reload.hpp"
#include "protocols/canopen/dynamic_mapping.hpp"
#include "protocols/canopen/eds.hpp"
#include "protocols/line/net/line_server.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/session.hpp"
#include "protocols/udp_debug/messages.hpp"
#include "protocols/udp_debug/net/udp_debug_service.hpp"
#include "scripting/engine.hpp"
#include "server/canopen_bus.hpp"
#include "server/canopen_part.hpp"
#include "server/clock_driver.hpp"
#include "server/drive_image.hpp"
#include "server/plant_settings.hpp"
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
  parse_canopen_config();
  build_drive();
  build_canopen();
  bind_listeners();
  build_script();
  build_steps();
  leds_.power_up(led::address_of(*od_));
}

DriveUnit::~DriveUnit() { shutdown(); }

void DriveUnit::build_drive() {
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

  spdlog::info("{}model {}: {} {}, XDD {}, {} controller, 6502h = 0x{:02X}", log_prefix_, preset_.name,
               preset_.identity.device_name, preset_.identity.software_version, preset_.xdd_file,
               preset_.is_rabbit() ? "RABBIT" : "standard", preset_.supported_modes);

  state_dir_ = std::make_unique<persistence::StateDir>(settings_.state_dir, number_);
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
    spdlog::info("{}--ip {} overrides the stored address {}", log_prefix_, settings_.ip, stored_ip);
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
  hooks.reset_script = [this] {  // a factory reset was applied (persistence.md §4 step 3)
    if (engine_) engine_->factory_reset();
  };
  hooks.after_restore = [this] {
    iofunc_->after_bulk_load();
    if (canopen_) canopen_->node().reload();
    wake();
  };
  persistence_ = std::make_unique<persistence::Service>(*od_, preset_.name, MCEMU_VERSION, std::move(factory),
                                                        std::move(on_file), *storage_, std::move(hooks));
  refgo_interpreter_ = std::make_unique<refgo::Interpreter>(*od_, *core_);
  iofunc_->power_on(stored_power_on_state());
}

// What a power on takes from outside the OD (persistence.md §2, §8): the plant position of the last
// clean shutdown (else the preset's power-on position) and the stored home offset, which the core
// applies only on absolute-encoder models.
core::PowerOnState DriveUnit::stored_power_on_state() const {
  core::PowerOnState s;
  s.raw_position_inc = state_dir_->load_plant(preset_.name);
  if (const auto& file = persistence_->on_file()) s.home_offset_inc = file->home_offset_inc;
  return s;
}

// drive-1.plant.json at clean shutdown (persistence.md §8), with the atomic procedure of §10.
void DriveUnit::write_plant_state() const {
  const auto text = persistence::serialize_plant(preset_.name, core_->raw_position_inc());
  if (auto error = persistence::write_atomically(state_dir_->plant_file(), text)) {
    spdlog::error("cannot write the plant state: {}", *error);
  }
}

// The active IP address: --ip given explicitly > stored 5007h > factory (persistence.md §6).
void DriveUnit::apply_explicit_ip() {
  if (!settings_.ip_explicit) return;
  const auto octets = parse_ipv4(settings_.ip, "--ip");
  std::vector<od::StoredValue> ip;
  for (std::uint8_t s = 1; s <= 4; ++s) ip.push_back({0x5007, s, od::Value{std::int64_t{octets[s - 1]}}});
  od_->load_values(ip);
}

// The four octets of 5007h (IP address) or 5008h (mask) as "A.B.C.D".
std::string DriveUnit::dotted_quad(std::uint16_t index) const {
  std::string out;
  for (std::uint8_t s = 1; s <= 4; ++s) {
    if (s > 1) out += '.';
    out += std::to_string(od_->number(index, s));
  }
  return out;
}

std::string DriveUnit::active_ip() const { return dotted_quad(0x5007); }
std::string DriveUnit::active_mask() const { return dotted_quad(0x5008); }

// One simulation step of 1 ms (drive-core.md §2), called by the clock driver; the RefGo programs
// (jog timer, Back & Forth) follow in the same drive time, then the CANopen node (its TPDOs see
// this step's values, its EMCYs come from this step's events).
void DriveUnit::step() { steps_->step(); }

void DriveUnit::sync() {
  if (clock_) clock_->sync();
}

void DriveUnit::wake() {
  if (clock_) {
    clock_->wake();
  } else {
    steps_->touch();
  }
}

// The parts that follow the drive in each step, in the order of drive-core.md §2.4 / iofunc.md §3:
// fault durations and the scope (router), the RefGo programs, the script engine (its sleeps, the
// compile step, held output), the shell's event hand-off (EMCY, UDP notes, LED status), the
// CANopen node (its TPDOs see this step's values).
void DriveUnit::build_steps() {
  struct RouterPart final : sim::Part {
    web::api::Router& router;
    const core::DriveCore& core;
    const od::ObjectDictionary& od;
    RouterPart(web::api::Router& r, const core::DriveCore& c, const od::ObjectDictionary& d)
        : router(r), core(c), od(d) {}
    void step() override { router.on_step(); }
    std::uint64_t quiet_steps() const override {
      const auto e = router.faults().next_expiry();
      return e ? sim::steps_before(*e, core.time_ms()) : sim::k_forever;
    }
    // The scope samples the (constant) values at every multiple of 5 ms a quiet stretch passed.
    void skip(std::uint64_t n) override {
      const std::uint64_t now = core.time_ms();  // after the core's skip
      const std::uint64_t from = now - std::min<std::uint64_t>(n, 60000) + 1;
      for (std::uint64_t t = (from + 4) / 5 * 5; t <= now; t += 5) router.scope().on_step(t, od);
    }
  };
  parts_.push_back(std::make_unique<RouterPart>(*router_, *core_, *od_));
  parts_.push_back(std::make_unique<sim::RefgoPart>(*refgo_interpreter_, *core_));
  parts_.push_back(script_part());
  parts_.push_back(std::make_unique<sim::HookPart>([this] { on_core_events(); }));
  parts_.push_back(std::make_unique<sim::FunctionPart>(canopen_part(*canopen_)));
  steps_ = std::make_unique<sim::DriveSteps>(*od_, *iofunc_, *core_);
  for (auto& p : parts_) steps_->add(*p);
}

void DriveUnit::on_core_events() {
  for (const auto& d : iofunc_->drain_diagnostics()) {
    if (d.level == core::DiagnosticLevel::warning) {
      spdlog::warn("I/O function: {}", d.text);
    } else {
      spdlog::debug("I/O function: {}", d.text);
    }
  }
  leds_.update_status(*core_, *od_);
  for (const auto& e : core_->drain_events()) {
    if (trace_) trace_->record(trace::Channel::drive, trace::Dir::event, core::event_text(e));  // web.md §8.6
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

void DriveUnit::parse_canopen_config() {
  try {
    slcan_config_ = slcan::slcan_config_from_json(settings_.config.value("slcan", nlohmann::json::object()));
    canopen_config_ = canopen::canopen_config_from_json(settings_.config.value("canopen", nlohmann::json::object()));
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("config: ") + e.what());
  }
}

void DriveUnit::build_canopen() {
  canopen::Node::Hooks hooks;
  hooks.reset_node = [this] {  // the drive part of a power cycle (persistence.md §7)
    core::PowerOnState keep{core_->raw_position_inc(), core_->home_offset_inc()};
    if (const auto& file = persistence_->on_file()) keep.home_offset_inc = file->home_offset_inc;
    spdlog::info("{}canopen: NMT reset node", log_prefix_);
    script_power_down();
    rebuild_ram_image();
    iofunc_->power_on(keep);                // the core's power_on() and iofunc's volatile state
    leds_.power_up(led::address_of(*od_));  // drive time restarts at 0
    on_core_events();
    script_power_up();  // no UDP start-up block: at once (scripting.md §3.2)
  };
  hooks.wake = [this] { wake(); };
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
void DriveUnit::rebuild_ram_image() {
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
  spdlog::info("{}drive image rebuilt from the factory image and the state file", log_prefix_);
}

// NMT reset communication: 1000h–1FFFh and 3404h.03 from the factory image and the file.
void DriveUnit::reload_communication_objects() {
  const auto& file = persistence_->on_file();
  canopen::reload_communication_objects(
      *od_, persistence_->factory().objects,
      file ? std::span<const od::StoredValue>(file->objects) : std::span<const od::StoredValue>());
}

std::string DriveUnit::script_id() const {
  const auto id = od_->read(0x3500, 1);
  if (id && std::holds_alternative<std::string>(*id) && !std::get<std::string>(*id).empty()) {
    return std::get<std::string>(*id);
  }
  return "(empty)";
}

void DriveUnit::start() {
  const auto log_listen = [&](const char* name, const char* proto, std::uint16_t port) {
    spdlog::info("{}listening: {} {} {}:{}", log_prefix_, name, proto, settings_.bind, port);
  };
  log_listen("refgo", "tcp", refgo_->port());
  log_listen("slcan", "tcp", slcan_->port());
  log_listen("http", "tcp", http_->port());
  log_listen("udp", "udp", udp_->local_endpoint().port());
  spdlog::info("{}drive IP address {} / {}", log_prefix_, active_ip(), active_mask());
  refgo_->start();
  slcan_->start();
  http_->start();
  udp_debug_->power_up(active_ip(), script_id());
  udp_debug_->start();
  power_up_network();
  script_power_up();
}

// Runs the drive to the CANopen node's boot-up before the loop serves any connection
// (docs/decisions/0004): "ready" means the node answers. After the UDP power-up block, so that
// notes of these first steps follow it.
void DriveUnit::power_up_network() {
  canopen_->power_on();
  for (int i = 0; i < 1000 && canopen_->node().state() == canopen::NmtState::initialising; ++i) step();
  wake();
}

// persistence.md §7, in its order: the core powers down (plant position kept and written) and the
// script engine is terminated, the RefGo and SLCAN connections are closed, the UDP listeners and backlog forgotten, the
// RAM image rebuilt from the file as it is now, the UDP start-up block produced again, the node boots, the script
// starts if the stored autostart flag is set. The HTTP server and its connections stay (the request that asked for it
// gets its answer). A Store still being written finishes first.
void DriveUnit::power_cycle(std::function<void()> done) {
  if (persistence_->in_flight() > 0) {
    auto timer = std::make_shared<asio::steady_timer>(io_, std::chrono::milliseconds(5));
    timer->async_wait([this, timer, alive = std::weak_ptr<DriveUnit*>(self_),
                       done = std::move(done)](const boost::system::error_code& ec) mutable {
      if (!ec && alive.lock()) power_cycle(std::move(done));
    });
    return;
  }
  sync();
  spdlog::info("{}power cycle", log_prefix_);
  write_plant_state();
  core::PowerOnState keep{core_->raw_position_inc(), core_->home_offset_inc()};
  if (const auto& file = persistence_->on_file()) keep.home_offset_inc = file->home_offset_inc;
  script_power_down();
  refgo_->close_connections();
  slcan_->close_connections();
  rebuild_ram_image();
  refgo_interpreter_->reset();
  iofunc_->power_on(keep);
  leds_.power_up(led::address_of(*od_));
  udp_debug_->power_cycle(active_ip(), script_id());
  power_up_network();
  on_core_events();
  script_power_up();
  done();
}

void DriveUnit::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  self_.reset();
  engine_.reset();  // kills a running script's process group
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
