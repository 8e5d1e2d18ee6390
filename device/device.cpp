#include "device/device.hpp"

#include <cstdio>
#include <utility>

#include "device/config_image.hpp"
#include "device/parts.hpp"
#include "device/plant_settings.hpp"
#include "drive/faults.hpp"
#include "drive/od/model_tables.hpp"
#include "drive/od/objects.hpp"
#include "protocols/canopen/comm_reload.hpp"
#include "protocols/canopen/dynamic_mapping.hpp"
#include "protocols/udp_debug/messages.hpp"

namespace mcemu::device {

namespace {

// The start values of the runtime settings (web.md §8.9): defaults, then "settings" of the config.
RuntimeSettings runtime_settings(const nlohmann::json& config) {
  RuntimeSettings s;
  const auto it = config.find("settings");
  if (it == config.end()) return s;
  if (auto error = apply_settings(s, *it)) throw ConfigError("invalid \"settings\" in --config: " + *error);
  return s;
}

std::string hex2(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%02X", v);
  return buf;
}

}  // namespace

Device::Device(Setup setup, Environment env)
    : setup_(std::move(setup)),
      env_(std::move(env)),
      preset_(make_preset(setup_.model, setup_.config)),
      config_(setup_.config) {
  personality_ = &personality_of(preset_);
  settings_ = runtime_settings(config_);
  try {
    slcan_config_ = slcan::slcan_config_from_json(config_.value("slcan", nlohmann::json::object()));
    canopen_config_ = canopen::canopen_config_from_json(config_.value("canopen", nlohmann::json::object()));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("config: ") + e.what());
  }
  build_dictionary();
  build_core();
  if (personality_->canopen) build_canopen();
  trace_ = std::make_unique<trace::Ring>(
      trace::Ring::Clocks{[this] { return core_->time_ms(); }, [this] { return env_.unix_ms ? env_.unix_ms() : 0; }});
  faults_ = std::make_unique<FaultInjections>(*od_, *core_);
  wire_faults();
  build_steps();
  leds_.power_up(led::address_of(*od_));
}

Device::~Device() = default;

void Device::log(LogLevel level, const std::string& text) const {
  if (env_.log) env_.log(level, text);
}

// persistence.md §5 steps 1–3: preset → dictionary → config objects = factory image; the state
// file bulk-loaded over it; an explicit --ip overlays 5007h.
void Device::build_dictionary() {
  if (personality_->canopen && canopen_config_.dynamic_pdo_mapping) {  // slcan-canopen.md §9.7
    auto entries = od::build_entries(preset_);
    canopen::make_mapping_dynamic(entries);
    od_ = std::make_unique<od::ObjectDictionary>(std::move(entries));
  } else {
    od_ = std::make_unique<od::ObjectDictionary>(preset_);
  }
  apply_config_objects(*od_, config_);
  factory_ = persistence::snapshot(*od_);
  log(LogLevel::info, "model " + preset_.name + ": " + preset_.identity.device_name + " " +
                          preset_.identity.software_version + ", XDD " + preset_.xdd_file + ", " +
                          (preset_.is_rabbit() ? "RABBIT" : "standard") + " controller, 6502h = 0x" +
                          hex2(preset_.supported_modes));
  if (env_.load_state) loaded_ = env_.load_state(*od_, preset_.name);
  const std::string stored_ip = active_ip();
  apply_explicit_ip();
  if (setup_.explicit_ip && loaded_ && stored_ip != active_ip()) {
    log(LogLevel::info, "--ip " + active_ip() + " overrides the stored address " + stored_ip);
  }
}

void Device::build_core() {
  try {
    core_ = std::make_unique<core::DriveCore>(preset_, *od_,
                                              setup_.plant ? *setup_.plant : plant_config_from_json(config_));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("invalid plant configuration in --config: ") + e.what());
  }
  // The I/O functions wrap the core: they step it and power it on (iofunc.md §3).
  io_ = std::make_unique<iofunc::IoFunctions>(*od_, *core_);

  persistence::ServiceHooks hooks;
  hooks.now_utc = [this] { return env_.now_utc ? env_.now_utc() : std::string("1970-01-01T00:00:00Z"); };
  hooks.log_info = [this](const std::string& text) { log(LogLevel::info, text); };
  hooks.log_error = [this](const std::string& text) { log(LogLevel::error, text); };
  hooks.operation_enabled = [this] { return core_->state() == core::PdsState::operation_enabled; };
  hooks.home_offset_inc = [this] { return core_->home_offset_inc(); };
  hooks.reset_script = [this] {  // a factory reset was applied (persistence.md §4 step 3)
    if (observers_.factory_reset) observers_.factory_reset();
  };
  hooks.after_restore = [this] {
    io_->after_bulk_load();
    if (canopen_) canopen_->node().reload();
    if (env_.wake) env_.wake();
  };
  persistence_ = std::make_unique<persistence::Service>(*od_, preset_.name, setup_.mcemu_version, factory_,
                                                        std::move(loaded_), *env_.storage, std::move(hooks));
  loaded_.reset();
  if (personality_->refgo) refgo_ = std::make_unique<refgo::Interpreter>(*od_, *core_);

  // What a power on takes from outside the OD (persistence.md §2, §8): the plant position of the
  // last clean shutdown (else the preset's power-on position) and the stored home offset, which the
  // core applies only on absolute-encoder models.
  core::PowerOnState s;
  if (env_.stored_plant_position) s.raw_position_inc = env_.stored_plant_position(preset_.name);
  if (const auto& file = persistence_->on_file()) s.home_offset_inc = file->home_offset_inc;
  if (setup_.power_on) io_->power_on(s);
}

void Device::build_canopen() {
  canopen::Node::Hooks hooks;
  hooks.reset_node = [this] { reset_node(); };
  hooks.wake = [this] {
    if (env_.wake) env_.wake();
  };
  hooks.reset_communication = [this] { reload_communication_objects(); };
  hooks.connection_lost = [this] {  // life guarding expired (slcan-canopen.md §5.2)
    core_->connection_lost();
    handle_events();
  };
  // EMCYs raised by an SDO/RPDO write go out after that write's SDO response (§2 ordering)
  hooks.after_od_write = [this] { handle_events(); };
  hooks.diagnostic = [this](const std::string& text) { log(LogLevel::debug, "canopen: " + text); };
  canopen_ = std::make_unique<CanopenBus>(*od_, slcan_config_, canopen_config_, std::move(hooks));
}

// Fault injection reports on the trace (channel api) and, with udpEmulatorNotes, as a UDP note.
void Device::wire_faults() {
  faults_->set_journal([this](const std::string& trace_text, const std::string& note_text) {
    trace_->record(trace::Channel::api, trace::Dir::event, trace_text);
    if (settings_.udp_emulator_notes && env_.note) env_.note(note_text);
  });
}

// The parts that follow the drive in each step, in the order of drive-core.md §2.4 / iofunc.md §3:
// fault durations, the scope, the RefGo programs, the shell's parts (the script engine), the event
// hand-off (EMCY, UDP notes, LED status), the CANopen node (its TPDOs see this step's values).
void Device::build_steps() {
  std::vector<sim::Part*> order;
  if (parts_.empty()) {
    parts_.push_back(std::make_unique<FaultsPart>(*faults_, *core_));
    parts_.push_back(std::make_unique<ScopePart>(scope_, *core_, *od_));
    if (refgo_) parts_.push_back(std::make_unique<RefgoPart>(*refgo_, *core_));
    parts_.push_back(std::make_unique<sim::HookPart>([this] { handle_events(); }));
    if (canopen_) parts_.push_back(std::make_unique<CanopenPart>(*canopen_));
  }
  steps_ = std::make_unique<sim::DriveSteps>(*od_, *io_, *core_);
  const std::size_t before_hand_off = parts_.size() - (canopen_ ? 2 : 1);
  for (std::size_t i = 0; i < before_hand_off; ++i) steps_->add(*parts_[i]);
  for (auto& p : extras_) steps_->add(*p);
  for (std::size_t i = before_hand_off; i < parts_.size(); ++i) steps_->add(*parts_[i]);
}

void Device::add_part(std::unique_ptr<sim::Part> part) {
  extras_.push_back(std::move(part));
  build_steps();
}

std::optional<Refusal> Device::change_settings(const nlohmann::json& changes, const std::function<void()>& accepted) {
  RuntimeSettings next = settings_;
  if (auto error = apply_settings(next, changes)) return Refusal{Refusal::Kind::syntax, *error};
  settings_ = next;
  if (accepted) accepted();
  if (observers_.settings_changed) observers_.settings_changed(settings_);
  return std::nullopt;
}

void Device::handle_events() {
  for (const auto& d : io_->drain_diagnostics()) {
    log(d.level == core::DiagnosticLevel::warning ? LogLevel::warning : LogLevel::debug, "I/O function: " + d.text);
  }
  leds_.update_status(*core_, *od_);
  for (const auto& e : core_->drain_events()) {
    trace_->record(trace::Channel::drive, trace::Dir::event, core::event_text(e));  // web.md §8.6
    if (const auto* emcy = std::get_if<core::Emcy>(&e)) {
      if (canopen_) canopen_->node().emit_emcy(emcy->code, emcy->reg, emcy->data);
    } else if (const auto* f = std::get_if<core::FaultRaised>(&e)) {
      if (env_.note) env_.note(udp_debug::fault_text(f->code));
    } else if (std::holds_alternative<core::FaultResetDone>(e)) {
      if (env_.note) env_.note("fault cleared");
    }
    if (env_.event_tap) env_.event_tap(e);
  }
}

// Runs the drive to the CANopen node's boot-up before the loop serves any connection
// (docs/decisions/0004): "ready" means the node answers.
void Device::power_up_network() {
  if (canopen_) {
    canopen_->power_on();
    for (int i = 0; i < 1000 && canopen_->node().state() == canopen::NmtState::initialising; ++i) step();
  }
  if (env_.wake) env_.wake();
}

core::PowerOnState Device::power_on_state_for_restart() const {
  core::PowerOnState keep{core_->raw_position_inc(), core_->home_offset_inc()};
  if (const auto& file = persistence_->on_file()) keep.home_offset_inc = file->home_offset_inc;
  return keep;
}

void Device::power_cycle() {
  const auto keep = power_on_state_for_restart();
  rebuild_ram_image();
  if (refgo_) refgo_->reset();
  io_->power_on(keep);
  leds_.power_up(led::address_of(*od_));
}

void Device::reset_node() {
  const auto keep = power_on_state_for_restart();
  log(LogLevel::info, "canopen: NMT reset node");
  if (observers_.powering_down) observers_.powering_down();
  rebuild_ram_image();
  io_->power_on(keep);                    // the core's power_on() and iofunc's volatile state
  leds_.power_up(led::address_of(*od_));  // drive time restarts at 0
  handle_events();
  if (observers_.powered_up) observers_.powered_up();  // no UDP start-up block: at once (scripting.md §3.2)
}

// NMT reset node and power cycle (persistence.md §5, §7): RAM image = factory image (preset, then
// --config "objects") overlaid with the file as it is on disk now, then an explicit --ip. Live
// values, constants and command entries are the core's and the OD's own.
void Device::rebuild_ram_image() {
  std::vector<od::StoredValue> image;
  od_->for_each([&](const od::EntryInfo& e, const od::Value&) {
    if (e.cls == od::EntryClass::param || e.cls == od::EntryClass::comm || e.cls == od::EntryClass::proc) {
      image.push_back({e.index, e.sub, e.factory});
    }
  });
  od_->load_values(image);
  apply_config_objects(*od_, config_);
  if (const auto& file = persistence_->on_file()) od_->load_values(file->objects);
  apply_explicit_ip();
  log(LogLevel::info, "drive image rebuilt from the factory image and the state file");
}

// NMT reset communication: 1000h–1FFFh and 3404h.03 from the factory image and the file.
void Device::reload_communication_objects() {
  const auto& file = persistence_->on_file();
  canopen::reload_communication_objects(
      *od_, persistence_->factory().objects,
      file ? std::span<const od::StoredValue>(file->objects) : std::span<const od::StoredValue>());
}

// The active IP address: --ip given explicitly > stored 5007h > factory (persistence.md §6).
void Device::apply_explicit_ip() {
  if (!setup_.explicit_ip || !od_->find(od::k_ip_address, 1)) return;
  std::vector<od::StoredValue> ip;
  for (std::uint8_t s = 1; s <= 4; ++s) {
    ip.push_back({od::k_ip_address, s, od::Value{std::int64_t{(*setup_.explicit_ip)[s - 1]}}});
  }
  od_->load_values(ip);
}

std::string Device::dotted_quad(std::uint16_t index) const {
  if (!od_->find(index, 1)) return {};
  std::string out;
  for (std::uint8_t s = 1; s <= 4; ++s) {
    if (s > 1) out += '.';
    out += std::to_string(od_->number(index, s));
  }
  return out;
}

std::string Device::active_ip() const { return dotted_quad(od::k_ip_address); }
std::string Device::active_mask() const { return dotted_quad(od::k_ip_mask); }

std::string Device::script_id() const {
  const auto id = od_->read(od::k_script, 1);
  if (id && std::holds_alternative<std::string>(*id) && !std::get<std::string>(*id).empty()) {
    return std::get<std::string>(*id);
  }
  return "(empty)";
}

std::optional<od::Value> Device::factory_value(std::uint16_t index, std::uint8_t sub) const {
  for (const auto& sv : persistence_->factory().objects) {
    if (sv.index == index && sv.sub == sub) return sv.value;
  }
  return std::nullopt;
}

std::unique_ptr<od::ObjectDictionary> Device::factory_dictionary() const {
  auto od = std::make_unique<od::ObjectDictionary>(preset_);
  od->load_values(persistence_->factory().objects);
  return od;
}

}  // namespace mcemu::device
