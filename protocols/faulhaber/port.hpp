// The binary RS232 port of one FAULHABER drive (faulhaber.md §2, §4–§6), shared by every
// connection to it: one receiver per connection, one command dispatcher on the drive's object
// dictionary, responses to the requesting connection only, asynchronous messages (boot,
// statusword, EMCY) to every connection.
//
// Contract (pure, single-threaded, event-loop thread; no sockets — the shared line adapter
// protocols/line/net owns the connections):
// - make_session() gives a line::StreamSession for the adapter. It detaches itself when
//   destroyed and may outlive the port (adapter handlers run late): then it is silent.
// - Time is drive time, asked through Hooks::now (without it: the last step() time). It drives the
//   receiver's 50 ms inter-byte timeout and the response delay.
// - Ordering (§5): a request's response is queued first; then Hooks::after_request runs, where the
//   owner drains the drive core's events and calls notify_statusword()/notify_emcy(), so the
//   notifications a request caused follow its response. A reset node telegram has no response:
//   Hooks::reset_node runs (the owner performs the device reset and calls send_boot()), then
//   after_request. The hooks must not destroy the port.
// - Asynchronous messages read 0x2400.04 (bit 16 EMCY, bit 17 boot + statusword) and 0x2400.05
//   (net mode: none) when sent; frames carry the node-id 0x2400.03 read when sent (a request is
//   answered with the id it was addressed to, so a write of 0x2400.03 answers with the old id and
//   the next request needs the new one). A frame for another node-id is ignored.
// - response_delay: each response is held back that long in drive time; a connection's output
//   keeps its order (a notification waits behind a held response of that connection). The port
//   then reports next_deadline(); the owner calls step(now) at or after it. A write the dictionary
//   answers `pending` (Store/Restore) holds back that connection's later output likewise until it
//   completes.
// - Output limit: when a connection's untaken plus held-back output passes queue_limit_bytes, the
//   session stops (finished(), input ignored, trace "closing") and hands everything over at once;
//   the adapter, configured with close_on_overflow and pause_above = queue_limit_bytes, closes it.
//   A closed connection has no effect on the drive.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "drive/od/dictionary.hpp"
#include "protocols/faulhaber/commands.hpp"
#include "protocols/faulhaber/frame.hpp"
#include "protocols/faulhaber/receiver.hpp"
#include "protocols/line/stream_session.hpp"

namespace mcemu::faulhaber {

struct PortConfig {
  Millis response_delay{0};                   // faulhaber.response_delay_ms
  std::size_t queue_limit_bytes = 64 * 1024;  // faulhaber.queue_limit_bytes
  Millis inter_byte_timeout = Receiver::k_default_timeout;
};

// One trace line of a connection (channel `faulhaber`). The texts are views into the session's
// reused buffers: valid during the trace call only (copy what you keep).
struct TraceEvent {
  enum class Kind : std::uint8_t {
    rx,       // a frame received: hex + summary ("SDO read 6041.00")
    tx,       // a frame sent: hex + summary ("SDO read 6041.00 → 0x0427")
    dropped,  // bytes the receiver discarded: hex (garbage: the first 16) + reason
    ignored,  // a frame for another node-id: summary only (its rx event came before)
    event,    // "closing: queue overflow"
  };
  Kind kind = Kind::event;
  std::string_view hex;
  std::string_view summary;
  std::uint8_t command = 0;  // rx, tx: the frame's command byte (the master lint tells responses from notifications)
};

// The text of one event on the trace channel `faulhaber`: "dropped "/"ignored " for those kinds,
// the hex, " | " when both parts are there, the summary — e.g. `53 07 01 01 41 60 00 73 45 | SDO
// read 6041.00`. `out` is cleared first and its capacity reused: a connection's steady stream of
// frames builds no string.
void trace_line(const TraceEvent& e, std::string& out);

// Entries the port reads (faulhaber.md §6).
inline constexpr std::uint16_t k_rs232_index = 0x2400;
inline constexpr std::uint8_t k_node_id_sub = 0x03;
inline constexpr std::uint8_t k_settings_sub = 0x04;
inline constexpr std::uint8_t k_net_mode_sub = 0x05;
inline constexpr std::uint32_t k_emcy_bit = 1u << 16;
inline constexpr std::uint32_t k_async_bit = 1u << 17;
inline constexpr std::uint32_t k_ignore_crc_bit = 1u << 23;
// Used when the dictionary lacks the entry (factory values of §6).
inline constexpr std::uint8_t k_default_node_id = 1;
inline constexpr std::uint32_t k_default_settings = 0x00030000;

class Port {
 public:
  struct Hooks {
    std::function<Millis()> now;          // drive time
    std::function<void()> after_request;  // after each handled request, its response queued
    std::function<void()> reset_node;     // reset node telegram: device reset, then send_boot()
  };
  using Trace = std::function<void(const TraceEvent&)>;

  Port(od::ObjectDictionary& od, PortConfig config, Hooks hooks = {});
  ~Port();
  Port(const Port&) = delete;
  Port& operator=(const Port&) = delete;

  // `trace`: every frame of this connection in both directions, drops and events; may be empty.
  std::unique_ptr<line::StreamSession> make_session(Trace trace = {});

  // Asynchronous messages to every connection, when enabled (§6).
  void notify_statusword(std::uint16_t statusword);  // one per change of 6041h; bit 17, not net mode
  void notify_emcy(std::uint16_t code, std::uint8_t error_register, std::uint16_t error_word);  // bit 16
  void send_boot();  // after power on and after a device reset; device name 1008h; bit 17

  // Held-back output (response_delay, completed Store): when step() must run next.
  std::optional<Millis> next_deadline() const;
  void step(Millis now);

  // The settings in force now (read from the dictionary).
  std::uint8_t node_id() const;
  bool crc_check() const;
  bool emcy_enabled() const;
  bool async_enabled() const;
  bool net_mode() const;
  std::size_t session_count() const;

 private:
  class Session;
  struct Registry;
  Millis now() const;
  std::uint32_t settings() const;
  void broadcast(const Frame& f);
  void wake_sessions();

  od::ObjectDictionary& od_;
  PortConfig config_;
  Hooks hooks_;
  Commands commands_;
  std::shared_ptr<Registry> registry_;
  std::optional<od::Handle> node_id_;
  std::optional<od::Handle> settings_;
  std::optional<od::Handle> net_mode_;
  Millis last_step_{0};
  std::uint64_t next_session_id_ = 1;
};

}  // namespace mcemu::faulhaber
