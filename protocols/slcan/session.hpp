// One SLCAN client connection (slcan-canopen.md §3): cuts the byte stream into lines, answers each
// complete line exactly once (CR, `z\r`/`Z\r`, query replies, or BEL), hands valid client frames to
// the bus, and queues the node's frames as `t…\r` lines while the session is OPEN or LISTEN.
//
// Contract (single-threaded, event-loop thread; pure — no sockets, no clock):
// - Implements line::StreamSession for the shared TCP line adapter. A new session is OPEN,
//   timestamps off, and sends nothing until the client sends a line.
// - Ordering (§2): for a frame line the acknowledgement is queued first, then `to_node` is called;
//   whatever the node sends in reply comes back through deliver() inside that call and is queued
//   after the acknowledgement.
// - Output cap (§3.1): enforced by the TCP adapter, which owns the write queue (the server sets
//   its close-on-overflow limit to slcan.queue_limit_bytes); the session never drops output.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "protocols/can/frame.hpp"
#include "protocols/line/line_assembler.hpp"
#include "protocols/line/stream_session.hpp"
#include "protocols/slcan/codec.hpp"
#include "protocols/slcan/config.hpp"

namespace mcemu::slcan {

enum class ChannelState : std::uint8_t { open, listen, closed };

// What a session reports for the trace of §11.2 (channel `slcan`).
struct TraceEvent {
  enum class Dir : std::uint8_t { rx, tx, event } dir;
  std::string text;       // raw line (rx: as received, with its CR or LF; tx: with CR/BEL) or event text
  bool overlong = false;  // rx only
};

class Session final : public line::StreamSession {
 public:
  using ToNode = std::function<void(const can::Frame&)>;
  using SerialSource = std::function<std::uint32_t()>;  // 3404h.04
  using Trace = std::function<void(const TraceEvent&)>;

  static constexpr std::size_t k_max_line = 64;

  Session(SlcanConfig config, ToNode to_node, SerialSource serial);

  void receive(std::string_view bytes) override;
  std::string take_output() override;
  void peer_closed() override;
  bool finished() const override { return peer_closed_; }

  // A frame sent by the node; queued if this session is OPEN or LISTEN (§3.3). `stamp` is the
  // simulated time since the drive's power on (used only after Z1).
  void deliver(const can::Frame& frame, std::chrono::milliseconds stamp);
  void set_trace(Trace trace) { trace_ = std::move(trace); }
  // slcan.bel (slcan-canopen.md §11.3): asked once per complete line that is not over-long; true =
  // the line is answered `\a` instead of its normal reply and has no other effect.
  void set_bel_fault(std::function<bool()> bel) { bel_ = std::move(bel); }
  // slcan.rawTx: `text` is written to this client as it is, in any session state.
  void send_raw(std::string_view text);

  ChannelState state() const { return state_; }
  bool timestamps() const { return timestamps_; }
  // Remembered parameters that have no effect over TCP (§3.4).
  int bitrate_code() const { return bitrate_code_; }

 private:
  void handle_line(const line::Line& l);
  void apply(const Command& c);
  void reply(std::string_view text);
  void queue(std::string_view text, bool from_node);
  void event(std::string text);
  void set_state(ChannelState s);

  SlcanConfig config_;
  ToNode to_node_;
  SerialSource serial_;
  Trace trace_;
  std::function<bool()> bel_;
  line::LineAssembler assembler_{k_max_line, line::keep_all};
  std::string output_;
  ChannelState state_ = ChannelState::open;
  bool timestamps_ = false;
  bool peer_closed_ = false;
  int bitrate_code_ = -1;
  std::uint32_t btr_ = 0;
  std::uint32_t acceptance_code_ = 0;
  std::uint32_t acceptance_mask_ = 0xFFFFFFFF;
};

}  // namespace mcemu::slcan
