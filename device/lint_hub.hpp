// The master lint of one drive bundle (docs/lint.md, lint/README.md "Wiring"): the engine and the
// producers that feed it. The bundle's parts call the producer functions where they already trace;
// each adds the drive time and what the lint needs of the drive (6041h and 6061h after a write, the
// CANopen classification of a frame, the connection being served).
//
// Contract: pure, single-threaded (event-loop thread). With mode off every producer returns at
// once (the bundle does not even install the dictionary's write tap). Sessions made by wrap() and
// faulhaber_trace() may outlive the hub (the adapter destroys connections late): they are silent
// then. The connection scope (serve()) nests; a write outside every scope has connection 0.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "base/liveness.hpp"
#include "drive/drive_core.hpp"
#include "drive/od/dictionary.hpp"
#include "lint/engine.hpp"
#include "protocols/can/frame.hpp"
#include "protocols/canopen/types.hpp"
#include "protocols/faulhaber/port.hpp"
#include "protocols/line/stream_session.hpp"

namespace mcemu::device {

class LintHub {
 public:
  LintHub(lint::Config config, od::ObjectDictionary& od, const core::DriveCore& core, lint::Engine::Sink sink);
  LintHub(const LintHub&) = delete;
  LintHub& operator=(const LintHub&) = delete;

  lint::Engine& engine() { return engine_; }
  const lint::Engine& engine() const { return engine_; }
  bool active() const { return engine_.active(); }

  // ---- the connection being served (trace connection id; 0 = none)
  class Serving {
   public:
    Serving(const Serving&) = delete;
    Serving& operator=(const Serving&) = delete;
    ~Serving() {
      hub_.conn_ = conn_;
      hub_.chunk_ = chunk_;
    }

   private:
    friend class LintHub;
    Serving(LintHub& hub, lint::Conn conn, std::uint64_t chunk) : hub_(hub), conn_(hub.conn_), chunk_(hub.chunk_) {
      hub.conn_ = conn;
      hub.chunk_ = chunk;
    }
    LintHub& hub_;
    lint::Conn conn_;
    std::uint64_t chunk_;
  };
  // Dictionary writes and protocol requests inside the scope carry `conn` (an HTTP request, one read
  // of a line connection); `chunk` identifies that read (0 = none).
  [[nodiscard]] Serving serve(lint::Conn conn, std::uint64_t chunk = 0) { return Serving(*this, conn, chunk); }
  lint::Conn serving() const { return conn_; }

  // A line session whose every receive() is one read served in `conn`'s scope; destroying it is
  // ConnectionClosed.
  std::unique_ptr<line::StreamSession> wrap(std::unique_ptr<line::StreamSession> inner, lint::Conn conn);
  // The trace of a FAULHABER connection, wrapped: rx = a request (reset node: one without reply),
  // ignored = no reply, tx = its response or, command 0x05, the statusword notification; boot and
  // EMCY messages are neither. `trace` is called as before.
  faulhaber::Port::Trace faulhaber_trace(lint::Conn conn, faulhaber::Port::Trace trace);

  // ---- producers
  void od_write(const od::WriteNote& n);  // the dictionary's write tap
  void core_event(const core::Event& e);  // the bundle's event hand-off
  void powered_on();                      // after the core's power_on()
  void can_frame(const can::Frame& f, std::uint8_t node_id);
  void can_sent(const can::Frame& f, std::uint8_t node_id);  // a frame the node sent
  void nmt(canopen::NmtState from, canopen::NmtState to);
  void request(lint::Link link, lint::Conn conn, bool expects_reply);  // chunk: the current read's
  void reply(lint::Link link, lint::Conn conn, lint::ReplyKind kind);
  void closed(lint::Conn conn);
  void script_loop(lint::ScriptKind script, std::uint64_t statements_without_wait);
  void flash(lint::FlashKind kind, od::Origin origin);

 private:
  class Session;
  lint::Ms now() const { return core_.time_ms(); }
  std::int64_t number(const std::optional<od::Handle>& h) const { return h ? od_.number(*h) : 0; }

  od::ObjectDictionary& od_;
  const core::DriveCore& core_;
  lint::Engine engine_;
  std::optional<od::Handle> statusword_;
  std::optional<od::Handle> controlword_;
  std::optional<od::Handle> mode_;
  std::optional<od::Handle> mode_display_;
  std::optional<od::Handle> target_velocity_;
  lint::Conn conn_ = 0;
  std::uint64_t chunk_ = 0;
  std::uint64_t next_chunk_ = 0;
  base::LivenessToken alive_;
};

}  // namespace mcemu::device
