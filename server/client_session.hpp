// The session of one RefGo or SLCAN client as the drive sees it, wrapped around the protocol's own
// session (refgo::Session, the SLCAN bus session):
// - drive time is brought up to date before its input runs (the clock sleeps while the drive is
//   idle, docs/clock.md) and the clock is woken after it (a command may have started a move);
// - the connection counts for the yellow LINK/ACT LED and its traffic flickers it (morse-led.md §5);
// - connect and disconnect are UDP emulator notes (udp-debug.md §4.7) and trace events (web.md §8.6);
// - with a reply verdict (RefGo, web.md §9) each reply unit the inner session hands to reply() is
//   traced and sent, dropped (refgo.noReply) or held back in wall time (refgo.delay) by the pure
//   decision of device/fault_gates.hpp; a timer brings held-back replies out in order.
// The protocol behaviour is the inner session's.
//
// Contract: event-loop thread. `owner` is the drive unit's liveness: a connection's last handler may
// run after the unit is gone, and then no hook is called.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "base/liveness.hpp"
#include "device/fault_gates.hpp"
#include "protocols/line/stream_session.hpp"
#include "trace/trace.hpp"

namespace mcemu::server {

class ClientSession final : public line::StreamSession {
 public:
  struct Hooks {
    std::function<void()> sync;
    std::function<void()> wake;
    std::function<void(bool opened)> link;              // LED: a counted connection opened / closed
    std::function<void()> activity;                     // LED: traffic
    std::function<void(const std::string& text)> note;  // empty: no notes (udp-debug.md §4.7 names RefGo)
    // This connection's trace (channel, conn and peer bound); empty: no trace.
    std::function<void(trace::Dir dir, std::string_view text, trace::Flags flags)> trace;
    std::function<device::Verdict()> reply_verdict;  // empty: replies pass through the inner session
    // A reply unit was sent (true; a held-back one when it goes out) or dropped by refgo.noReply (false).
    std::function<void(bool sent)> replied;
  };

  // `what` names the client in notes ("refgo client 127.0.0.1").
  ClientSession(std::unique_ptr<line::StreamSession> inner, base::Liveness owner, Hooks hooks, std::string what,
                boost::asio::any_io_executor executor);
  ~ClientSession() override;
  ClientSession(const ClientSession&) = delete;
  ClientSession& operator=(const ClientSession&) = delete;

  void receive(std::string_view bytes) override;
  std::string take_output() override;
  void peer_closed() override;
  bool finished() const override { return inner_->finished() && ready_.empty() && held_.empty(); }
  bool paused() const override { return inner_->paused(); }
  void closing(std::string_view reason) override;

  // One reply unit of the inner session (refgo::Session's reply sink).
  void reply(std::string text);
  void trace(trace::Dir dir, std::string_view text, trace::Flags flags = {}) const;

 private:
  using Ms = std::chrono::milliseconds;
  static Ms wall_now();
  bool alive() const { return owner_.alive(); }
  void sent() const;  // hooks_.replied(true)
  // Appends the replies that may go now; arms the timer for the next held-back one.
  void release(std::string& out);

  std::unique_ptr<line::StreamSession> inner_;
  base::Liveness owner_;
  Hooks hooks_;
  std::string what_;
  std::string ready_;                    // replies that may be sent, in order
  device::DelayLine<std::string> held_;  // replies held back by refgo.delay
  boost::asio::steady_timer timer_;
  std::optional<Ms> armed_;    // the due time the timer waits for
  base::LivenessToken token_;  // the timer's handler checks this session is alive
};

}  // namespace mcemu::server
