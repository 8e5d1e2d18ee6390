// One emulated drive (design.md "A fleet is N copies of one drive bundle"): dictionary, core, I/O
// functions, persistence, RefGo interpreter, CANopen node, fault injections, LEDs, trace ring and
// its four listeners, wired together. Nothing in a unit knows that other units exist; the App
// (server/app.hpp) owns the units and the one clock that steps them. Everything runs on the one
// io_context thread; only the persistence worker runs beside it.
//
// The unit is split by role: drive_unit.cpp (the drive: build, steps, power cycle, shutdown),
// drive_listeners.cpp (RefGo, SLCAN and UDP listeners and their sessions), drive_web.cpp (the JSON
// API's services, the HTTP server and the WebSocket hub), drive_script.cpp (the MovingCap CODE
// script engine: its callbacks, step part, lock-step with the manual clock, power and settings).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/system/system_error.hpp>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/led/leds.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/slcan/config.hpp"
#include "server/settings.hpp"
#include "sim/drive_steps.hpp"
#include "trace/trace.hpp"

namespace mcemu::line {
class StreamSession;
}
namespace mcemu::refgo {
class Interpreter;
}
namespace mcemu::udp_debug::net {
class UdpDebugService;
}
namespace mcemu::line::net {
class LineServer;
struct PeerInfo;
}  // namespace mcemu::line::net
namespace mcemu::web::net {
class HttpServer;
}
namespace mcemu::web::api {
class Router;
}
namespace mcemu::persistence {
class Service;
class StateDir;
class WorkerStorage;
}  // namespace mcemu::persistence

namespace mcemu::iofunc {
class IoFunctions;
}
namespace mcemu::scripting {
class ScriptEngine;
}
namespace mcemu::web::api {
class ScriptControl;
}

namespace mcemu::server {

class CanopenBus;
class ClockDriver;

// A start-up failure that ends the process with one line and exit status 1 (e.g. a port in use).
struct StartupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DriveUnit {
 public:
  // Builds the drive and binds its four ports; throws StartupError or UsageError. `settings` are
  // this drive's own (server/fleet.hpp); `number` is k of drive-k.json; `log_prefix` starts every
  // log line of this unit ("" for a single drive, "drive 2: " in a fleet).
  DriveUnit(boost::asio::io_context& io, Settings settings, int number, std::string log_prefix);
  ~DriveUnit();
  DriveUnit(const DriveUnit&) = delete;
  DriveUnit& operator=(const DriveUnit&) = delete;

  // Logs the listeners, accepts connections, produces the UDP start-up block and runs the drive to
  // the CANopen node's boot-up (docs/decisions/0004).
  void start();
  // One simulation step of 1 ms (drive-core.md §2): the I/O functions (which step the core), then
  // the parts in order — fault durations and the scope, the RefGo programs, the event hand-off,
  // the CANopen node (sim/drive_steps.hpp).
  void step();
  // What the clock advances (quiet stretches skipped exactly, docs/clock.md).
  sim::Steppable& steps() { return *steps_; }
  // The process's clock (App): sync() before a client's input reads or changes the drive, wake()
  // after something outside a step changed it; mode and advance for the JSON API.
  // Also sets how the script engine interpolates ticks_us (real clock only, scripting.md §8.2).
  void attach_clock(ClockDriver& clock);
  // --clock manual lock-step (scripting.md §8.2): true while the script woken by a step has not
  // settled again; the clock is resumed (ClockDriver::resume) once it has.
  bool script_holds_clock();
  void shutdown();  // stop accepting, close sessions, finish pending stores, write the plant state
  // persistence.md §7: power loss and power-up in the running process; `done` when powered up.
  void power_cycle(std::function<void()> done);
  int number() const { return number_; }

  od::ObjectDictionary& od() { return *od_; }
  core::DriveCore& drive_core() { return *core_; }
  // The UDP debug console (udp-debug.md): status lines, notes, power_cycle().
  udp_debug::net::UdpDebugService& udp_debug() { return *udp_debug_; }

 private:
  void build_drive();
  void bind_listeners();
  std::unique_ptr<line::StreamSession> make_refgo_session(const line::net::PeerInfo& peer);
  std::unique_ptr<line::StreamSession> make_slcan_session(const line::net::PeerInfo& peer);
  std::function<void(trace::Dir, std::string_view, trace::Flags)> connection_trace(trace::Channel channel,
                                                                                   const line::net::PeerInfo& peer);
  // drive_transport.cpp: the transport fault injections and the UDP and drive trace taps.
  void wire_transport();
  void run_transport_actions();
  void on_core_events();
  void build_steps();
  std::unique_ptr<sim::Part> script_part();  // drive_script.cpp
  void sync();
  void wake();
  void power_up_network();  // UDP start-up block and the CANopen boot-up of a power-up
  void build_web(const boost::asio::ip::address& address);
  void wire_websocket();
  std::string dotted_quad(std::uint16_t index) const;
  std::string active_ip() const;
  void apply_explicit_ip();
  core::PowerOnState stored_power_on_state() const;
  void write_plant_state() const;
  std::string active_mask() const;
  std::string script_id() const;
  // drive_script.cpp
  class ScriptWeb;
  web::api::ScriptControl& script_control();  // the JSON API's view of the engine (build_web)
  void build_script();
  void script_power_down();  // the engine is terminated, the stored script loaded (persistence.md §7)
  void script_power_up();    // autostart if the stored flag is set (after the start-up block)
  void apply_script_settings(bool strict, std::int64_t memory_mib, bool trace_calls);
  // CANopen node on the SLCAN port (slcan-canopen.md): bus, and the NMT resets it asks for.
  void parse_canopen_config();
  void build_canopen();
  void rebuild_ram_image();
  void reload_communication_objects();

  boost::asio::io_context& io_;
  Settings settings_;
  int number_;
  std::string log_prefix_;
  model::ModelPreset preset_;
  std::unique_ptr<od::ObjectDictionary> od_;
  std::unique_ptr<core::DriveCore> core_;
  std::unique_ptr<iofunc::IoFunctions> iofunc_;  // steps and powers the core (iofunc.md §3)
  std::unique_ptr<persistence::StateDir> state_dir_;
  std::unique_ptr<persistence::WorkerStorage> storage_;
  std::unique_ptr<persistence::Service> persistence_;
  std::unique_ptr<refgo::Interpreter> refgo_interpreter_;
  std::unique_ptr<line::net::LineServer> refgo_;
  std::unique_ptr<line::net::LineServer> slcan_;
  std::unique_ptr<trace::Ring> trace_;
  std::shared_ptr<web::api::Router> router_;  // shared with the HTTP handler
  std::unique_ptr<web::net::HttpServer> http_;
  std::unique_ptr<boost::asio::ip::udp::socket> udp_;
  // shared: RefGo sessions that outlive the App (in the io_context's handlers) hold weak references
  std::shared_ptr<udp_debug::net::UdpDebugService> udp_debug_;
  slcan::SlcanConfig slcan_config_;
  canopen::CanopenConfig canopen_config_;
  std::unique_ptr<CanopenBus> canopen_;
  led::Leds leds_;
  std::unique_ptr<web::api::ScriptControl> script_web_;  // a ScriptWeb
  std::unique_ptr<scripting::ScriptEngine> engine_;      // after the dictionary, core, interpreter, trace
  bool hold_waiting_ = false;                            // a lock-step resume is registered with the engine
  bool clock_manual_ = false;
  std::vector<std::unique_ptr<sim::Part>> parts_;
  std::unique_ptr<sim::DriveSteps> steps_;
  ClockDriver* clock_ = nullptr;
  // Handlers that may run after the unit is gone (sessions, timers) hold a weak reference.
  std::shared_ptr<DriveUnit*> self_ = std::make_shared<DriveUnit*>(this);
  std::set<std::uint64_t> lit_http_;  // HTTP connections that count for LINK/ACT (morse-led.md §5.1)
  bool shut_down_ = false;
};

// "2026-01-15T10:15:02Z", "2026-01-15T10:15:02.123Z" and "20260115T101502Z" of the current UTC time.
std::string utc_iso8601();
std::string utc_iso8601_ms();
std::int64_t unix_ms_now();  // UTC, ms since 1970 (the trace ring's wall clock)
std::string utc_compact();

// Turns a bind failure into the one start-up line of the spec README (naming the port's flag).
[[noreturn]] void bind_failed(const std::string& service, const std::string& bind, std::uint16_t port,
                              const std::string& flag, const boost::system::system_error& e);

}  // namespace mcemu::server
