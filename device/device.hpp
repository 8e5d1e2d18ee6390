// One emulated drive as a pure bundle (design.md "A fleet is N copies of one drive bundle"): its
// dictionary, drive core, I/O functions, LEDs, trace ring, fault injections and transport gates,
// scope, runtime settings, persistence service, the protocol sessions its personality has (RefGo
// interpreter and CANopen bus for a MovingCap) and the step parts the clock advances. No sockets,
// no Asio, no clock reads, no logging: the shell (server/drive_unit.hpp) gives it an Environment
// — the state file as loaded, the storage that writes it, the wall clock for the trace, a log sink
// and the clock's wake — and binds listeners for the services of its personality. The HTTP router
// (web/api), the line sessions and the script engine consult it.
//
// Contract: single-threaded (event-loop thread); everything it owns lives as long as it does.
// Construction throws ConfigError for an invalid config value (a one-line message).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "device/canopen_bus.hpp"
#include "device/faults.hpp"
#include "device/lint_hub.hpp"
#include "device/personality.hpp"
#include "device/refusal.hpp"
#include "device/runtime_settings.hpp"
#include "device/scope.hpp"
#include "drive/drive_core.hpp"
#include "drive/led/leds.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "iofunc/io_functions.hpp"
#include "lint/config.hpp"
#include "persistence/service.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/faulhaber/config.hpp"
#include "protocols/faulhaber/port.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/slcan/config.hpp"
#include "scripting/basic/programs.hpp"
#include "sim/drive_steps.hpp"
#include "trace/trace.hpp"

namespace mcemu::device {

// What a bundle is built from: the drive's model and its --config document.
// The largest trace ring a "trace": {"events": N} section may ask for (~70 MB when full).
inline constexpr std::size_t k_max_trace_events = 1'000'000;

struct Setup {
  std::string model = "MC349";
  // The drive's config document: "objects", "model_overrides", "plant", "homing", "slcan",
  // "canopen", "settings", "trace" (docs/reference/persistence.md §5, models.md, web.md §8.9,
  // §8.6).
  nlohmann::json config = nlohmann::json::object();
  // --ip given explicitly: overlays 5007h after the state file (persistence.md §6).
  std::optional<std::array<std::uint8_t, 4>> explicit_ip;
  std::string mcemu_version = "0.0.0";
  // Plant and homing settings given as a value (tests); nullopt: the "plant"/"homing" sections.
  std::optional<core::PlantConfig> plant;
  // --lint off|warn|strict: overrides "lint.mode" of the config (docs/lint.md §3).
  std::optional<lint::Mode> lint_mode;
  // --clock manual: drive time stands still between requests, so the lint's timing rules are off
  // unless the "lint" section sets "timing" itself.
  bool manual_clock = false;
  // false: the drive core stays unpowered until its owner powers it on (tests of the power-on).
  bool power_on = true;
};

enum class LogLevel : std::uint8_t { debug, info, warning, error };

// What the shell gives a bundle. Every member may be empty except `storage`.
struct Environment {
  // Writes the state file (persistence/worker_storage.hpp in the server, memory in tests).
  persistence::Storage* storage = nullptr;
  // Loads the state file of this model into the dictionary (start-up step 2 of persistence.md §5)
  // and returns its image; nullopt when there is none. Called once, after the factory image.
  std::function<std::optional<persistence::Image>(od::ObjectDictionary&, const std::string& model)> load_state;
  // The plant position of the last clean shutdown (persistence.md §8), read once at start-up.
  std::function<std::optional<std::int64_t>(const std::string& model)> stored_plant_position;
  std::function<std::int64_t()> unix_ms;  // wall clock of trace events (0 without)
  std::function<std::string()> now_utc;   // "2026-01-15T10:15:02Z" for the state file
  std::function<void(LogLevel, const std::string&)> log;
  std::function<void()> wake;  // something outside a step changed the drive: the clock re-plans
  // An "mcemu: <text>" note on the UDP console (udp-debug.md §4.7); the bundle calls it only for
  // its own notes (faults, fault injections with udpEmulatorNotes on).
  std::function<void(const std::string& text)> note;
  // Files of the drive's own part of the state directory besides the state file — the MC BASIC
  // programs and variables (faulhaber.md §9.1, §9.8: "faulhaber/program3.bas"). Reads happen once at
  // start-up; writes are crash-safe and in order (the persistence worker). Empty: nothing kept.
  std::function<std::optional<std::string>(const std::string& name)> read_state_file;
  std::function<void(const std::string& name, std::string contents)> write_state_file;
  // Every core event the hand-off drains, after the bundle has handled it (tests, fuzz oracles).
  std::function<void(const core::Event&)> event_tap;
};

// What the shell does around a power cycle or an NMT reset node (persistence.md §7) — the script
// engine, connections, UDP — and after a change of the runtime settings. Each may be empty.
struct Observers {
  std::function<void()> powering_down;  // before the RAM image is rebuilt
  std::function<void()> powered_up;     // after the drive runs again
  std::function<void()> factory_reset;  // a factory reset was applied (the script is replaced)
  std::function<void(const RuntimeSettings&)> settings_changed;
};

class Device {
 public:
  Device(Setup setup, Environment env);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const Personality& personality() const { return *personality_; }
  const model::ModelPreset& preset() const { return preset_; }
  const nlohmann::json& config() const { return config_; }

  od::ObjectDictionary& od() { return *od_; }
  const od::ObjectDictionary& od() const { return *od_; }
  core::DriveCore& core() { return *core_; }
  const core::DriveCore& core() const { return *core_; }
  // The I/O functions of a MovingCap; null on a drive without them (FAULHABER).
  iofunc::IoFunctions* io() { return io_.get(); }
  led::Leds& leds() { return leds_; }
  trace::Ring& trace() { return *trace_; }
  FaultInjections& faults() { return *faults_; }
  TransportFaults& transport_faults() { return faults_->transport(); }
  Scope& scope() { return scope_; }
  const RuntimeSettings& settings() const { return settings_; }
  persistence::Service& persistence() { return *persistence_; }
  // The sessions of the personality; null when it has none.
  refgo::Interpreter* refgo() { return refgo_.get(); }
  const refgo::Interpreter* refgo() const { return refgo_.get(); }
  CanopenBus* canopen() { return canopen_.get(); }
  faulhaber::Port* faulhaber_port() { return fh_port_.get(); }
  // MC BASIC (faulhaber.md §9); null on a drive without it. Change programs and the autostart
  // through the bundle's calls below, which keep them in the state directory.
  const basic::Programs* basic() const { return basic_.get(); }
  basic::Programs* basic() { return basic_.get(); }
  basic::Programs::Upload upload_program(int slot, std::string_view text);
  bool set_basic_autostart(int slot);
  // The SAVE count since power on (AN165: the EEPROM's write cycles are limited).
  std::uint64_t basic_saves() const { return basic_vars_ ? basic_vars_->saves() : 0; }
  const faulhaber::FaulhaberConfig& faulhaber_config() const { return fh_config_; }
  const slcan::SlcanConfig& slcan_config() const { return slcan_config_; }
  // The master lint (docs/lint.md): its engine (GET/DELETE /api/v1/lint) and its producers (the
  // shell's sessions report requests, replies and the connection being served).
  LintHub& lint() { return *lint_; }
  const LintHub& lint() const { return *lint_; }

  // What the clock advances (quiet stretches skipped exactly, docs/clock.md).
  sim::DriveSteps& steps() { return *steps_; }
  // One 1 ms step (drive-core.md §2.4): the I/O functions (which step the core), then the parts.
  void step() { steps_->step(); }
  // Adds a part stepped after the RefGo programs and before the event hand-off (the script engine).
  void add_part(std::unique_ptr<sim::Part> part);

  void set_observers(Observers o) { observers_ = std::move(o); }

  // Applies a change of the runtime settings (web.md §8.9): all or nothing. An accepted change is
  // journaled first (`accepted`: the API's trace event and note, sent under the old UDP setting),
  // then the observers are told.
  std::optional<Refusal> change_settings(const nlohmann::json& changes, const std::function<void()>& accepted = {});

  // The event hand-off after every full step and every write from outside a step: core events go to
  // the trace (channel drive), EMCYs to the CANopen node, faults to the UDP notes, the core state
  // to the STATUS LED, I/O function diagnostics to the log.
  void handle_events();

  // Start of mcemu: runs the drive to the CANopen node's boot-up (docs/decisions/0004).
  void power_up_network();
  // persistence.md §7, the drive's part of a power cycle: the RAM image is rebuilt from the state
  // file as it is now, the drive powers on where the axis stands, the node boots.
  void power_cycle();

  // "A.B.C.D" of 5007h (active IP address) and 5008h (mask).
  std::string active_ip() const;
  std::string active_mask() const;
  // 3500h.01, "(empty)" for the placeholder (udp-debug.md §4.1).
  std::string script_id() const;
  // The factory value of an entry (the persistence factory image), nullopt if it has none.
  std::optional<od::Value> factory_value(std::uint16_t index, std::uint8_t sub) const;
  // A dictionary holding the factory image (EDS export).
  std::unique_ptr<od::ObjectDictionary> factory_dictionary() const;

 private:
  void log(LogLevel level, const std::string& text) const;
  void build_dictionary();
  void build_core();
  persistence::Image factory_image() const;  // persistence.md §5 steps 1–3
  void build_lint();
  void on_finding(const lint::Finding& f);
  void build_canopen();
  void build_faulhaber();
  void device_reset();
  void build_basic();
  void load_basic_files();
  void save_basic_state();  // FAULHABER reset node telegram: the drive part of a power cycle, then the boot message
  void build_steps();
  void wire_faults();
  void apply_explicit_ip();
  void rebuild_ram_image();
  void reload_communication_objects();
  void power_on(const core::PowerOnState& state);
  void reset_node();  // NMT reset node: the drive part of a power cycle (persistence.md §7)
  core::PowerOnState power_on_state_for_restart() const;
  std::string dotted_quad(std::uint16_t index) const;

  Setup setup_;
  Environment env_;
  const Personality* personality_;
  model::ModelPreset preset_;
  nlohmann::json config_;
  slcan::SlcanConfig slcan_config_;
  canopen::CanopenConfig canopen_config_;
  lint::Config lint_config_;
  std::unique_ptr<od::ObjectDictionary> od_;
  std::optional<persistence::Image> loaded_;  // the state file at start-up, until the service owns it
  std::unique_ptr<core::DriveCore> core_;
  std::unique_ptr<LintHub> lint_;
  std::unique_ptr<iofunc::IoFunctions> io_;
  std::unique_ptr<persistence::Service> persistence_;
  std::unique_ptr<refgo::Interpreter> refgo_;
  std::unique_ptr<CanopenBus> canopen_;
  faulhaber::FaulhaberConfig fh_config_;
  std::unique_ptr<faulhaber::Port> fh_port_;
  std::unique_ptr<basic::MemoryVariables> basic_vars_;
  std::unique_ptr<basic::Programs> basic_;
  bool fh_quiet_ = false;
  bool has_1002_ =
      true;  // the fault injections watch 1002h themselves  // a power on: its statusword changes are not notified
  std::unique_ptr<trace::Ring> trace_;
  std::unique_ptr<FaultInjections> faults_;
  Scope scope_;
  RuntimeSettings settings_;
  RuntimeSettings start_settings_;  // from the config file: what HTTP may not relax
  led::Leds leds_;
  Observers observers_;
  std::vector<std::unique_ptr<sim::Part>> parts_;   // the bundle's own parts
  std::vector<std::unique_ptr<sim::Part>> extras_;  // parts added by the shell (add_part)
  std::unique_ptr<sim::DriveSteps> steps_;
};

}  // namespace mcemu::device
