// The wiring of one drive bundle (device/device.hpp) to its sockets: the listeners its personality
// names, the HTTP server and WebSocket hub, the UDP console, the script engine, the state directory
// and the persistence worker. Nothing in a unit knows that other units exist; the App
// (server/app.hpp) owns the units and the one clock that steps them. Everything runs on the one
// io_context thread; only the persistence worker runs beside it.
//
// The unit is split by role: drive_unit.cpp (build, power cycle, shutdown), drive_listeners.cpp
// (RefGo, SLCAN and UDP listeners and their sessions), drive_transport.cpp (transport fault
// injections and trace taps), drive_web.cpp (the JSON API's services, the HTTP server and the
// WebSocket hub), drive_script.cpp (the MovingCap CODE script engine: its callbacks, step part,
// lock-step with the manual clock, power and settings).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/system/system_error.hpp>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "base/connection_ids.hpp"
#include "base/liveness.hpp"
#include "device/device.hpp"
#include "server/client_session.hpp"
#include "server/settings.hpp"
#include "trace/trace.hpp"

namespace mcemu::udp_debug::net {
class UdpDebugService;
}
namespace mcemu::line::net {
class LineServer;
class PtyServer;
struct PeerInfo;
}  // namespace mcemu::line::net
namespace mcemu::web::net {
class HttpServer;
}
namespace mcemu::web::api {
class Router;
class ScriptControl;
}  // namespace mcemu::web::api
namespace mcemu::persistence {
class Service;
class StateDir;
class WorkerStorage;
}  // namespace mcemu::persistence

namespace mcemu::scripting {
class ScriptEngine;
}

namespace mcemu::server {

class ClockDriver;

// A start-up failure that ends the process with one line and exit status 1 (e.g. a port in use).
struct StartupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DriveUnit {
 public:
  // Builds the drive and binds the ports of its personality; throws StartupError or UsageError.
  // `settings` are this drive's own (server/fleet.hpp); `number` is k of drive-k.json;
  // `log_prefix` starts every log line of this unit ("" for a single drive, "drive 2: " in a fleet).
  DriveUnit(boost::asio::io_context& io, Settings settings, int number, std::string log_prefix);
  ~DriveUnit();
  DriveUnit(const DriveUnit&) = delete;
  DriveUnit& operator=(const DriveUnit&) = delete;

  // Logs the listeners, accepts connections, produces the UDP start-up block and runs the drive to
  // the CANopen node's boot-up (docs/decisions/0004).
  void start();
  // One simulation step of 1 ms (the bundle's, device/device.hpp).
  void step() { device_->step(); }
  // What the clock advances (quiet stretches skipped exactly, docs/clock.md).
  sim::Steppable& steps() { return device_->steps(); }
  // The process's clock (App): sync() before a client's input reads or changes the drive, wake()
  // after something outside a step changed it, settle() before a read or change that is no
  // client's input (server/clock_driver.hpp); mode and advance for the JSON API.
  // Also sets how the script engine interpolates ticks_us (real clock only, scripting.md §8.2).
  // `script_runs` (App): counts the units whose script engine has a run, this one included while
  // it has (scripting::EngineCallbacks::run_changed).
  void attach_clock(ClockDriver& clock, std::size_t* script_runs = nullptr);
  // --clock manual lock-step (scripting.md §8.2): true while the script woken by a step has not
  // settled again; the clock is resumed (ClockDriver::resume) once it has.
  bool script_holds_clock();
  void shutdown();  // stop accepting, close sessions, finish pending stores, write the plant state
  // persistence.md §7: power loss and power-up in the running process; `done` when powered up.
  void power_cycle(std::function<void()> done);
  int number() const { return number_; }
  // The ports the unit listens on (0: a service its personality does not have).
  struct Ports {
    std::uint16_t refgo = 0;
    std::uint16_t slcan = 0;
    std::uint16_t http = 0;
    std::uint16_t udp = 0;
  };
  Ports ports() const;

  device::Device& device() { return *device_; }
  od::ObjectDictionary& od() { return device_->od(); }
  core::DriveCore& drive_core() { return device_->core(); }
  // The UDP debug console (udp-debug.md): status lines, notes, power_cycle().
  udp_debug::net::UdpDebugService& udp_debug() { return *udp_debug_; }

 private:
  device::Environment environment();
  void bind_listeners();
  void bind_udp(const boost::asio::ip::address& address);
  std::unique_ptr<line::StreamSession> make_refgo_session(const line::net::PeerInfo& peer);
  std::unique_ptr<line::StreamSession> make_slcan_session(const line::net::PeerInfo& peer);
  std::unique_ptr<line::StreamSession> make_faulhaber_session(const line::net::PeerInfo& peer);
  void open_faulhaber_pty();
  std::function<void(trace::Dir, std::string_view, trace::Flags)> connection_trace(trace::Channel channel,
                                                                                   const line::net::PeerInfo& peer);
  ClientSession::Hooks client_hooks(bool notes);
  // drive_transport.cpp: the transport fault injections and the UDP and drive trace taps.
  void wire_transport();
  void wire_canopen_faults();
  void wire_udp_taps();
  void run_transport_actions();
  void sync();
  void wake();
  void settle();
  void note(const std::string& text);
  void build_web(const boost::asio::ip::address& address);
  void wire_websocket();
  void write_plant_state() const;
  // drive_script.cpp
  class ScriptWeb;
  web::api::ScriptControl& script_control();  // the JSON API's view of the engine (build_web)
  void build_script();
  std::unique_ptr<sim::Part> script_part();
  void script_power_down();  // the engine is terminated, the stored script loaded (persistence.md §7)
  void script_power_up();    // autostart if the stored flag is set (after the start-up block)
  void apply_script_settings(const device::RuntimeSettings& s);

  boost::asio::io_context& io_;
  Settings settings_;
  int number_;
  std::string log_prefix_;
  std::unique_ptr<persistence::StateDir> state_dir_;
  std::unique_ptr<persistence::WorkerStorage> storage_;
  std::unique_ptr<device::Device> device_;
  std::unique_ptr<line::net::LineServer> refgo_;
  std::unique_ptr<line::net::LineServer> slcan_;
  std::unique_ptr<line::net::LineServer> faulhaber_;
  std::unique_ptr<line::net::PtyServer> faulhaber_pty_;
  std::unique_ptr<web::api::Router> router_;
  std::unique_ptr<web::net::HttpServer> http_;
  std::unique_ptr<boost::asio::ip::udp::socket> udp_;
  // shared: RefGo sessions that outlive the App (in the io_context's handlers) hold weak references
  std::shared_ptr<udp_debug::net::UdpDebugService> udp_debug_;
  std::unique_ptr<web::api::ScriptControl> script_web_;  // a ScriptWeb
  bool script_run_ = false;  // the engine has a run (counted in *script_runs_); before engine_, whose end may report it
  std::size_t* script_runs_ = nullptr;
  std::unique_ptr<scripting::ScriptEngine> engine_;  // after the bundle and the UDP service
  bool hold_waiting_ = false;                        // a lock-step resume is registered with the engine
  bool clock_manual_ = false;
  ClockDriver* clock_ = nullptr;
  // Handlers that may run after the unit is gone (sessions, timers) hold a weak reference.
  base::LivenessToken alive_;
  std::set<std::uint64_t> lit_http_;
  // One counter of connection ids for the RefGo, SLCAN and HTTP listeners: no two connections of
  // this drive show the same `conn` in the trace (web.md §8.6).
  std::shared_ptr<base::ConnectionIds> conn_ids_ =
      std::make_shared<base::ConnectionIds>();  // HTTP connections that count for LINK/ACT (morse-led.md §5.1)
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
