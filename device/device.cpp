#include "device/device.hpp"

#include <climits>
#include <cstdio>
#include <utility>

#include "device/config_image.hpp"
#include "device/json_fields.hpp"
#include "device/parts.hpp"
#include "device/plant_settings.hpp"
#include "drive/faults.hpp"
#include "drive/od/model_tables.hpp"
#include "drive/od/objects.hpp"
#include "lint/reporter.hpp"
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

// The "lint" section (docs/lint.md §3) under --lint and --clock manual (the timing rules compare drive
// time, which stands still between the requests of a manual clock: off unless the section says).
lint::Config lint_config(const nlohmann::json& config, const Setup& setup) {
  const auto it = config.find("lint");
  const nlohmann::json section = it == config.end() ? nlohmann::json::object() : *it;
  if (!section.is_object()) throw std::invalid_argument("lint: must be an object");
  lint::Config c = lint::config_from_json(section);
  if (setup.lint_mode) c.mode = *setup.lint_mode;
  if (setup.manual_clock && !section.contains("timing")) c.timing = false;
  return c;
}

// The "trace" section: {"events": N}, the size of the drive's trace ring (web.md §8.6: 10 000 by
// default). A large fleet of moving drives may keep fewer: a full ring holds ~70 bytes per event.
std::size_t trace_events(const nlohmann::json& config) {
  const auto it = config.find("trace");
  if (it == config.end()) return trace::Ring::k_default_capacity;
  if (!it->is_object()) throw ConfigError("config: \"trace\" must be an object");
  std::size_t events = trace::Ring::k_default_capacity;
  for (const auto& [key, value] : it->items()) {
    if (key != "events") throw ConfigError("config: unknown key \"trace." + key + "\"");
    const auto n = json_uint(value, 1, k_max_trace_events);
    if (!n) throw ConfigError("config: \"trace.events\" must be an integer 1 … " + std::to_string(k_max_trace_events));
    events = static_cast<std::size_t>(*n);
  }
  return events;
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
  start_settings_ = settings_;
  try {
    slcan_config_ = slcan::slcan_config_from_json(config_.value("slcan", nlohmann::json::object()));
    canopen_config_ = canopen::canopen_config_from_json(config_.value("canopen", nlohmann::json::object()));
    if (config_.contains("faulhaber")) fh_config_ = faulhaber::faulhaber_config_from_json(config_["faulhaber"]);
    lint_config_ = lint_config(config_, setup_);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("config: ") + e.what());
  }
  build_dictionary();
  build_core();
  if (personality_->canopen) build_canopen();
  if (personality_->faulhaber) build_faulhaber();
  if (personality_->basic) build_basic();
  trace_ = std::make_unique<trace::Ring>(
      trace::Ring::Clocks{[this] { return core_->time_ms(); }, [this] { return env_.unix_ms ? env_.unix_ms() : 0; }},
      trace_events(config_));
  faults_ = std::make_unique<FaultInjections>(*od_, *core_);
  has_1002_ = od_->find(0x1002, 0).has_value();
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
    constexpr std::uint32_t k_dynamic_mapping = 1;                     // the layout variant of od::preset_layout
    od_ = std::make_unique<od::ObjectDictionary>(od::preset_layout(preset_, k_dynamic_mapping, [this] {
      auto entries = od::build_entries(preset_);
      canopen::make_mapping_dynamic(entries);
      return entries;
    }));
  } else {
    od_ = std::make_unique<od::ObjectDictionary>(preset_);
  }
  apply_config_objects(*od_, config_);  // the factory image (factory_image()) ends here
  log(LogLevel::info,
      "model " + preset_.name + ": " + preset_.identity.device_name + " " + preset_.identity.software_version +
          (preset_.xdd_file.empty() ? std::string() : ", XDD " + preset_.xdd_file) + ", " +
          (preset_.is_rabbit() ? "RABBIT" : "standard") + " controller, 6502h = 0x" + hex2(preset_.supported_modes));
  if (env_.load_state) loaded_ = env_.load_state(*od_, preset_.name);
  const std::string stored_ip = active_ip();
  apply_explicit_ip();
  if (setup_.explicit_ip && loaded_ && stored_ip != active_ip()) {
    log(LogLevel::info, "--ip " + active_ip() + " overrides the stored address " + stored_ip);
  }
}

// persistence.md §5 steps 1–3 again, on a dictionary of its own: the same layout and --config
// objects give the same image whenever it is made, so it is made only when asked for.
persistence::Image Device::factory_image() const {
  od::ObjectDictionary fresh(od_->layout());
  apply_config_objects(fresh, config_);
  return persistence::snapshot(fresh);
}

void Device::build_core() {
  try {
    core_ = std::make_unique<core::DriveCore>(preset_, *od_,
                                              setup_.plant ? *setup_.plant : plant_config_from_json(config_));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("invalid plant configuration in --config: ") + e.what());
  }
  build_lint();
  // The I/O functions wrap the core: they step it and power it on (iofunc.md §3).
  if (personality_->io_functions) io_ = std::make_unique<iofunc::IoFunctions>(*od_, *core_);

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
    if (io_) io_->after_bulk_load();
    if (canopen_) canopen_->node().reload();
    if (env_.wake) env_.wake();
  };
  persistence_ = std::make_unique<persistence::Service>(
      *od_, preset_.name, setup_.mcemu_version, [this] { return factory_image(); }, std::move(loaded_), *env_.storage,
      std::move(hooks));
  loaded_.reset();
  if (personality_->refgo) refgo_ = std::make_unique<refgo::Interpreter>(*od_, *core_);

  // What a power on takes from outside the OD (persistence.md §2, §8): the plant position of the
  // last clean shutdown (else the preset's power-on position) and the stored home offset, which the
  // core applies only on absolute-encoder models.
  core::PowerOnState s;
  if (env_.stored_plant_position) s.raw_position_inc = env_.stored_plant_position(preset_.name);
  if (const auto& file = persistence_->on_file()) s.home_offset_inc = file->home_offset_inc;
  if (setup_.power_on) power_on(s);
}

void Device::power_on(const core::PowerOnState& state) {
  if (io_) {
    io_->power_on(state);  // the core's power_on() and iofunc's volatile state
  } else {
    core_->power_on(state);
  }
  lint_->powered_on();
}

// The master lint (docs/lint.md): one engine, fed through the dictionary's write tap (installed only
// when the lint is on: off costs nothing), the event hand-off, power on and the sessions.
void Device::build_lint() {
  lint_ = std::make_unique<LintHub>(lint_config_, *od_, *core_, [this](const lint::Finding& f) { on_finding(f); });
  if (lint_->active()) od_->set_write_tap([this](const od::WriteNote& n) { lint_->od_write(n); });
}

// A reported finding: the trace channel lint; error level also on the UDP console (a note, sent
// while udpEmulatorNotes is on).
void Device::on_finding(const lint::Finding& f) {
  const std::string text = lint::finding_text(f);
  if (trace_) trace_->record(trace::Channel::lint, trace::Dir::event, text, f.conn);
  if (f.severity == lint::Severity::error && env_.note) env_.note("lint " + text);
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
  if (lint_->active()) {
    CanopenBus::Observer o;
    o.client_frame = [this](const can::Frame& f) { lint_->can_frame(f, canopen_->node().node_id()); };
    o.node_frame = [this](const can::Frame& f) { lint_->can_sent(f, canopen_->node().node_id()); };
    o.nmt = [this](canopen::NmtState from, canopen::NmtState to) { lint_->nmt(from, to); };
    canopen_->set_observer(std::move(o));
  }
}

// The FAULHABER binary protocol (faulhaber.md §2–§6): one port for every connection of this drive.
// Responses first, then the notifications the request caused (after_request hands the core's
// events over); the reset node telegram is a device reset followed by the boot message.
void Device::build_faulhaber() {
  faulhaber::Port::Hooks hooks;
  hooks.now = [this] { return faulhaber::Millis(static_cast<std::int64_t>(core_->time_ms())); };
  hooks.after_request = [this] { handle_events(); };
  hooks.reset_node = [this] { device_reset(); };
  fh_port_ = std::make_unique<faulhaber::Port>(*od_, fh_config_.port, std::move(hooks));
}

void Device::device_reset() {
  log(LogLevel::info, "faulhaber: reset node");
  fh_quiet_ = true;
  reset_node();
  fh_quiet_ = false;
  if (fh_port_) fh_port_->send_boot();
  if (env_.wake) env_.wake();
}

// MC BASIC (faulhaber.md §9): eight program slots and the interpreter, stepped after the core; the
// program texts, the autostart number and the SAVEd variables live in the state directory.
void Device::build_basic() {
  basic::Settings bs;
  int autostart = 0;
  if (const auto it = config_.find("faulhaber"); it != config_.end()) {
    if (const auto n = it->find("basic_statements_per_ms"); n != it->end()) {
      // The bound keeps one drive step cheap: a step runs whole, and at 1000 the heaviest statement
      // there is costs about 0.7 ms per step (docs/faulhaber.md "Execution model").
      if (!n->is_number_unsigned() || n->get<std::uint64_t>() < 1 ||
          n->get<std::uint64_t>() > basic::k_max_statements_per_ms) {
        throw ConfigError("config: \"faulhaber.basic_statements_per_ms\" must be an integer 1 … " +
                          std::to_string(basic::k_max_statements_per_ms));
      }
      bs.statements_per_ms = static_cast<std::uint32_t>(n->get<std::uint64_t>());
    }
    if (const auto a = it->find("autostart"); a != it->end()) {
      if (!a->is_number_unsigned() || a->get<std::uint64_t>() > 8) {
        throw ConfigError("config: \"faulhaber.autostart\" must be a program number 0 … 8 (0 = none)");
      }
      autostart = static_cast<int>(a->get<std::uint64_t>());
    }
  }
  basic_vars_ = std::make_unique<basic::MemoryVariables>([this](const basic::MemoryVariables::Values& values) {
    nlohmann::json doc = nlohmann::json::object();
    for (std::size_t v = 0; v < values.size(); ++v) {
      if (values[v]) doc[std::string(1, static_cast<char>('a' + v))] = *values[v];
    }
    if (env_.write_state_file) env_.write_state_file("faulhaber/variables.json", doc.dump(1) + "\n");
  });
  basic_ = std::make_unique<basic::Programs>(*od_, *basic_vars_, std::move(bs), [this](const basic::Event& e) {
    trace_->record(trace::Channel::basic, trace::Dir::event, basic::describe(e));
    if (e.kind == basic::EventKind::save) lint_->flash(lint::FlashKind::program, od::Origin::script);  // AN165
    if (e.kind == basic::EventKind::error) log(LogLevel::warning, "MC BASIC: " + basic::describe(e));
  });
  basic_->set_autostart(autostart);
  load_basic_files();
}

// The state directory's MC BASIC files: program<n>.bas, variables.json ({"a": 5, …}) and
// basic.json ({"autostart": n}, written when the autostart is changed over the API).
void Device::load_basic_files() {
  if (!env_.read_state_file) return;
  for (int slot = 1; slot <= basic::Programs::k_slots; ++slot) {
    if (auto text = env_.read_state_file("faulhaber/program" + std::to_string(slot) + ".bas")) {
      if (basic_->upload(slot, *text) != basic::Programs::Upload::ok) {
        log(LogLevel::warning,
            "MC BASIC: faulhaber/program" + std::to_string(slot) + ".bas is larger than 4096 bytes; ignored");
      }
    }
  }
  if (auto text = env_.read_state_file("faulhaber/variables.json")) {
    const auto doc = nlohmann::json::parse(*text, nullptr, false);
    if (doc.is_object()) {
      for (const auto& [name, value] : doc.items()) {
        if (name.size() == 1 && name[0] >= 'a' && name[0] <= 'z' && value.is_number_integer() &&
            value.get<std::int64_t>() >= INT32_MIN && value.get<std::int64_t>() <= INT32_MAX) {
          basic_vars_->set(static_cast<std::uint8_t>(name[0] - 'a'),
                           static_cast<std::int32_t>(value.get<std::int64_t>()));
        }
      }
    } else {
      log(LogLevel::warning, "MC BASIC: faulhaber/variables.json is not a JSON object; SAVEd variables read as 0");
    }
  }
  if (auto text = env_.read_state_file("faulhaber/basic.json")) {
    const auto doc = nlohmann::json::parse(*text, nullptr, false);
    if (doc.is_object() && doc.contains("autostart") && doc["autostart"].is_number_unsigned()) {
      basic_->set_autostart(static_cast<int>(doc["autostart"].get<std::uint64_t>()));
    }
  }
}

void Device::save_basic_state() {
  if (env_.write_state_file) {
    env_.write_state_file("faulhaber/basic.json", nlohmann::json{{"autostart", basic_->autostart()}}.dump() + "\n");
  }
}

basic::Programs::Upload Device::upload_program(int slot, std::string_view text) {
  if (!basic_) return basic::Programs::Upload::bad_slot;
  const auto r = basic_->upload(slot, text);
  if (r == basic::Programs::Upload::ok && env_.write_state_file) {
    env_.write_state_file("faulhaber/program" + std::to_string(slot) + ".bas", std::string(text));
  }
  if (env_.wake) env_.wake();
  return r;
}

bool Device::set_basic_autostart(int slot) {
  if (!basic_ || !basic_->set_autostart(slot)) return false;
  save_basic_state();
  return true;
}

// Fault injection reports on the trace (channel api) and, with udpEmulatorNotes, as a UDP note.
void Device::wire_faults() {
  faults_->set_kind_filter([p = personality_](std::string_view kind) {
    const auto family = kind.substr(0, kind.find('.'));
    if (family == "refgo") return p->refgo;
    if (family == "slcan") return p->canopen;
    if (family == "udp") return p->udp_debug;
    if (family == "script") return p->code_scripts;
    return true;  // drive.*, http.error
  });
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
    if (basic_) parts_.push_back(std::make_unique<BasicPart>(*basic_, *core_, lint_.get()));
    parts_.push_back(std::make_unique<sim::HookPart>([this] { handle_events(); }));
    if (canopen_) parts_.push_back(std::make_unique<CanopenPart>(*canopen_));
    if (fh_port_) parts_.push_back(std::make_unique<FaulhaberPart>(*fh_port_, *core_));
  }
  steps_ = std::make_unique<sim::DriveSteps>(*od_, io_.get(), *core_);
  const std::size_t before_hand_off = parts_.size() - 1 - (canopen_ ? 1 : 0) - (fh_port_ ? 1 : 0);
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
  // docs/security.md: relaxing the script settings is for the command line and the config file
  if (auto why = relaxation(start_settings_, next)) return Refusal{Refusal::Kind::forbidden, *why};
  settings_ = next;
  if (accepted) accepted();
  if (observers_.settings_changed) observers_.settings_changed(settings_);
  return std::nullopt;
}

void Device::handle_events() {
  if (io_) {
    for (const auto& d : io_->drain_diagnostics()) {
      log(d.level == core::DiagnosticLevel::warning ? LogLevel::warning : LogLevel::debug, "I/O function: " + d.text);
    }
  }
  leds_.update_status(*core_, *od_);
  if (!has_1002_) faults_->observe_fault_bits(core_->fault_bits());
  for (const auto& e : core_->drain_events()) {
    lint_->core_event(e);
    trace_->record(trace::Channel::drive, trace::Dir::event, core::event_text(e));  // web.md §8.6
    if (const auto* emcy = std::get_if<core::Emcy>(&e)) {
      if (canopen_) canopen_->node().emit_emcy(emcy->code, emcy->reg, emcy->data);
      // FAULHABER layout (faulhaber.md §5 command 0x07): the 2320h error word in the first two bytes
      if (fh_port_ && !fh_quiet_) {
        fh_port_->notify_emcy(emcy->code, emcy->reg, static_cast<std::uint16_t>(emcy->data[0] | (emcy->data[1] << 8)));
      }
    } else if (const auto* sw = std::get_if<core::StatuswordChanged>(&e)) {
      if (fh_port_ && !fh_quiet_)
        fh_port_->notify_statusword(sw->new_value);  // one per change of 6041h (faulhaber.md §6)
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
  if (fh_port_) {
    // The statusword of the power on is not a change a host is told about: the boot message is
    // the first thing it hears (faulhaber.md §6).
    fh_quiet_ = true;
    handle_events();
    fh_quiet_ = false;
    fh_port_->send_boot();
  }
  if (basic_) basic_->start_autostart();  // faulhaber.md §9.1: after power on
  if (env_.wake) env_.wake();
}

core::PowerOnState Device::power_on_state_for_restart() const {
  core::PowerOnState keep{core_->raw_position_inc(), core_->home_offset_inc()};
  if (const auto& file = persistence_->on_file()) keep.home_offset_inc = file->home_offset_inc;
  return keep;
}

void Device::power_cycle() {
  const auto keep = power_on_state_for_restart();
  if (basic_) basic_->power_cycle();
  rebuild_ram_image();
  if (refgo_) refgo_->reset();
  power_on(keep);
  leds_.power_up(led::address_of(*od_));
}

void Device::reset_node() {
  const auto keep = power_on_state_for_restart();
  log(LogLevel::info, "canopen: NMT reset node");
  if (observers_.powering_down) observers_.powering_down();
  if (basic_) basic_->power_cycle();
  rebuild_ram_image();
  power_on(keep);
  leds_.power_up(led::address_of(*od_));  // drive time restarts at 0
  handle_events();
  if (basic_) basic_->start_autostart();               // faulhaber.md §9.1: after power on and after a device reset
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
