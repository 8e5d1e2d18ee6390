// The CANopen node behind the SLCAN port (slcan-canopen.md §2, §4–§10): NMT, SDO server, PDOs,
// SYNC consumer, EMCY producer, heartbeat producer and node guarding, composed from one small
// service per CiA 301 object.
//
// Contract (pure, single-threaded, event-loop thread):
// - Time comes in: `now` is simulated time (ms, monotonic, never going back). Frames go out as the
//   return values of on_frame() / advance(), in the order of §2 (SDO response; boot-up or guarding
//   reply; EMCYs in the order raised; TPDOs by ascending number; heartbeat). next_deadline() says
//   when advance() must be called next; the caller also calls advance() after every drive step, so
//   that TPDOs see changes made by the drive, RefGo, the web or scripts (§9.4).
// - Objects are read and written through the OD only (origin `sdo`); the node keeps no copy of a
//   communication parameter except what a running timer needs. It registers the 1017h write hook
//   and removes it in its destructor; the OD must outlive the node.
// - Inputs from the rest of the emulator: emit_emcy() for drive-core EMCY events, reload() after a
//   bulk load of the OD that did not come from the node (1011h Restore, power cycle by the web).
// - Outputs to the rest of the emulator, through Hooks: reset_node (the composition root performs
//   the drive's power cycle: OD rebuilt from factory image + stored file, core power_on);
//   reset_communication (1000h–1FFFh and 3404h.03 reloaded from factory image + stored file);
//   connection_lost (life guarding expired: drive-core connectionLost()); after_od_write (called
//   after every OD write the node makes, so the caller can drain drive-core events and hand EMCYs
//   back through emit_emcy() in the right place); diagnostic (trace text); wake (output became
//   available outside a processing call: a completed Store/Restore, an EMCY — call advance()).
// - Fault injection (slcan-canopen.md §11.3) through Faults: the SDO server's (sdo_server.hpp) and
//   heartbeat_stop, asked for every heartbeat that is due: true = that heartbeat is not produced
//   (the period runs on).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "protocols/can/frame.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/canopen/guarding.hpp"
#include "protocols/canopen/heartbeat.hpp"
#include "protocols/canopen/rpdo.hpp"
#include "protocols/canopen/sdo_server.hpp"
#include "protocols/canopen/tpdo.hpp"
#include "protocols/canopen/types.hpp"

namespace mcemu::canopen {

class Node {
 public:
  struct Hooks {
    std::function<void()> reset_node;
    std::function<void()> reset_communication;
    std::function<void()> connection_lost;
    std::function<void()> after_od_write;
    std::function<void(const std::string&)> diagnostic;
    std::function<void()> wake;
  };

  struct Faults {
    SdoFaults sdo;
    std::function<bool()> heartbeat_stop;
  };

  Node(od::ObjectDictionary& od, CanopenConfig config, Hooks hooks = {});
  ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  // Power on (mcemu start, web power cycle): INITIALISING, boot-up after the reset-communication
  // delay (10 ms), then PRE-OPERATIONAL. Applies the node-id of 3404h.03. Frames before that are
  // ignored.
  void power_on(Millis now);
  std::vector<can::Frame> on_frame(const can::Frame& frame, Millis now);
  std::vector<can::Frame> advance(Millis now);
  std::optional<Millis> next_deadline() const;

  // An EMCY of the drive (drive-core.md §11.2, §13 `Emcy`): sent on 1014h in PRE-OPERATIONAL and
  // OPERATIONAL with the next output (inside a processing call: that call's), dropped otherwise.
  void emit_emcy(std::uint16_t code, std::uint8_t error_register, const std::array<std::uint8_t, 5>& data = {});
  // After a bulk OD load not caused by the node: heartbeat, PDO, EMCY settings re-read; the node-id
  // in use is kept (§10, 1011h).
  void reload();

  void set_faults(Faults faults);

  NmtState state() const { return state_; }
  std::uint8_t node_id() const { return node_id_; }

 private:
  void begin(Millis now);
  std::vector<can::Frame> finish();
  void on_nmt(const can::Frame& f);
  void on_sdo(const can::Frame& f);
  void on_sync();
  void on_guarding_rtr();
  void set_state(NmtState next);
  void reset(bool whole_node);
  void life_guarding_expired();
  void apply_node_id_from_od();
  std::uint32_t cob(std::uint16_t index, std::uint8_t sub, std::uint32_t predefined_base) const;

  od::ObjectDictionary& od_;
  CanopenConfig config_;
  Hooks hooks_;
  std::function<bool()> heartbeat_stop_;
  SdoServer sdo_;
  TpdoSet tpdo_;
  RpdoSet rpdo_;
  HeartbeatProducer heartbeat_;
  NodeGuarding guarding_;
  NmtState state_ = NmtState::initialising;
  std::optional<Millis> bootup_at_;
  std::uint8_t node_id_ = 50;
  Millis now_{0};
  bool in_call_ = false;
  Outbox out_;
};

}  // namespace mcemu::canopen
