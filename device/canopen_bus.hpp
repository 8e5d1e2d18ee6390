// The one virtual CAN bus behind the SLCAN port (slcan-canopen.md §2, §3.7): the CANopen node and
// every SLCAN session. A client's frame goes to the node only; every frame the node sends goes to
// every session in OPEN or LISTEN, in the node's order, after the sender's acknowledgement.
//
// Contract (event-loop thread; no sockets here — the shared line adapter owns the connections and
// the per-session output cap):
// - make_session() creates a session attached to the bus; it detaches itself when destroyed, and
//   may outlive the bus (the adapter's connections can be destroyed after the server): a session
//   of a destroyed bus is silent and its frames go nowhere.
// - step(dt) advances simulated time and runs the node (heartbeat, timers, TPDO change detection);
//   the server calls it once per 1 ms drive step, after the drive core's step and after handing
//   the core's EMCY events to node().emit_emcy().
// - Frame timestamps (Z1) are simulated ms since power_on().
// - With canopen.dynamic_pdo_mapping the dictionary must have been built from
//   canopen::make_mapping_dynamic() entries; the bus then installs the §9.7 write rules.
// - Fault injection (slcan-canopen.md §11.3), through Faults: every node frame gets a verdict
//   (slcan.dropTx: sent to no session; slcan.delayTx: held back in wall time, order kept — the
//   server's timer calls release_delayed() at next_release()); slcan.bel is asked by every
//   session per line; send_raw() is slcan.rawTx.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "device/fault_gates.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/can/frame.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/canopen/node.hpp"
#include "protocols/line/stream_session.hpp"
#include "protocols/slcan/config.hpp"
#include "protocols/slcan/session.hpp"

namespace mcemu::slcan {
class Session;
}
namespace mcemu::canopen {
class DynamicMapping;
}

namespace mcemu::device {

class CanopenBus {
 public:
  CanopenBus(od::ObjectDictionary& od, slcan::SlcanConfig slcan, canopen::CanopenConfig canopen,
             canopen::Node::Hooks hooks = {});
  ~CanopenBus();
  CanopenBus(const CanopenBus&) = delete;
  CanopenBus& operator=(const CanopenBus&) = delete;

  struct Faults {
    std::function<device::Verdict(const can::Frame&)> node_frame;  // empty: every frame is sent
    std::function<bool()> bel;                                     // slcan.bel, per command line
    std::function<std::chrono::milliseconds()> wall_now;           // for held-back frames
    std::function<void(std::chrono::milliseconds due)> schedule;   // call release_delayed() then
    std::function<void(const std::string& text)> trace;            // a frame dropped or held back
  };
  void set_faults(Faults f) { faults_ = std::move(f); }

  // What the master lint sees of the bus (device/lint_hub.hpp); each member may be empty.
  struct Observer {
    std::function<void(const can::Frame&)> client_frame;  // a client's frame, before the node gets it
    std::function<void(const can::Frame&)> node_frame;    // each frame the node sends, before transport faults
    std::function<void(canopen::NmtState from, canopen::NmtState to)> nmt;  // the node's NMT state changed
  };
  void set_observer(Observer o) { observer_ = std::move(o); }
  // Sends the held-back frames whose time has come; asks for the next call through schedule().
  void release_delayed();
  std::optional<std::chrono::milliseconds> next_release() const { return delayed_.next_due(); }
  // slcan.rawTx: `text` to every session as it is.
  void send_raw(std::string_view text);

  // `trace`: the session's lines and events (slcan-canopen.md §11.2), may be empty.
  std::unique_ptr<line::StreamSession> make_session(slcan::Session::Trace trace = {});
  void power_on();  // node power on now: boot-up after 10 ms (web power cycle)
  // mcemu start: power on and run the node to its boot-up at once, before the port accepts
  // connections, so that "ready" means the node answers (the real drive booted long before any
  // client could connect, slcan-canopen.md §4.4).
  void start();
  void step(std::chrono::milliseconds dt = std::chrono::milliseconds(1));

  canopen::Node& node() { return *node_; }
  std::chrono::milliseconds now() const { return now_; }
  std::size_t session_count() const;

 private:
  class BusSession;
  struct Registry;  // shared with the sessions
  struct Stamped {
    can::Frame frame;
    std::chrono::milliseconds stamp;
  };
  void from_client(const can::Frame& frame);
  void broadcast(const std::vector<can::Frame>& frames);
  void deliver(const Stamped& f);
  void nmt_since(canopen::NmtState before);

  od::ObjectDictionary& od_;
  slcan::SlcanConfig slcan_;
  std::unique_ptr<canopen::DynamicMapping> dynamic_mapping_;  // only with canopen.dynamic_pdo_mapping
  std::unique_ptr<canopen::Node> node_;
  std::shared_ptr<Registry> registry_;
  std::chrono::milliseconds now_{0};
  std::chrono::milliseconds powered_at_{0};
  Faults faults_;
  Observer observer_;
  device::DelayLine<Stamped> delayed_;
};

}  // namespace mcemu::device
