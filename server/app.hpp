// The composition root of mcemu: owns the drive (dictionary, persistence, later the core and the
// protocol engines), the four listeners and the clock, and wires them together. Everything runs on
// the one io_context thread; only the persistence worker runs beside it.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <memory>
#include <stdexcept>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/slcan/config.hpp"
#include "server/settings.hpp"

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
class FaultInjections;
}
namespace mcemu::persistence {
class Service;
class StateDir;
class WorkerStorage;
}  // namespace mcemu::persistence

namespace mcemu::iofunc {
class IoFunctions;
}

namespace mcemu::server {

class ClockDriver;
class CanopenBus;

// A start-up failure that ends the process with one line and exit status 1 (e.g. a port in use).
struct StartupError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class App {
 public:
  // Builds the drive and binds all four ports; throws StartupError or UsageError.
  App(boost::asio::io_context& io, Settings settings);
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  void start();     // accept connections, start the clock
  void shutdown();  // stop accepting, close sessions, finish pending stores, write the plant state

  od::ObjectDictionary& od() { return *od_; }
  core::DriveCore& drive_core() { return *core_; }
  // The UDP debug console (udp-debug.md): status lines, notes, power_cycle().
  udp_debug::net::UdpDebugService& udp_debug() { return *udp_debug_; }

 private:
  void build_drive();
  void bind_listeners();
  void start_udp_receive();
  std::unique_ptr<line::StreamSession> make_refgo_session(const line::net::PeerInfo& peer);
  std::unique_ptr<line::StreamSession> make_slcan_session(const line::net::PeerInfo& peer);
  void step();
  void on_core_events();
  std::string dotted_quad(std::uint16_t index) const;
  std::string active_ip() const;
  void apply_explicit_ip();
  core::PowerOnState stored_power_on_state() const;
  void write_plant_state() const;
  std::string active_mask() const;
  std::string script_id() const;
  // CANopen node on the SLCAN port (slcan-canopen.md): bus, and the NMT resets it asks for.
  void parse_canopen_config();
  void build_canopen();
  void rebuild_ram_image();
  void reload_communication_objects();

  boost::asio::io_context& io_;
  Settings settings_;
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
  std::unique_ptr<web::api::FaultInjections> faults_;
  std::unique_ptr<web::net::HttpServer> http_;
  std::unique_ptr<boost::asio::ip::udp::socket> udp_;
  // shared: RefGo sessions that outlive the App (in the io_context's handlers) hold weak references
  std::shared_ptr<udp_debug::net::UdpDebugService> udp_debug_;
  std::unique_ptr<ClockDriver> clock_;
  slcan::SlcanConfig slcan_config_;
  canopen::CanopenConfig canopen_config_;
  std::unique_ptr<CanopenBus> canopen_;
  bool shut_down_ = false;
};

// "2026-01-15T10:15:02Z" and "20260115T101502Z" of the current UTC time.
std::string utc_iso8601();
std::string utc_compact();

}  // namespace mcemu::server
