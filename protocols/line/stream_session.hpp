// The interface between a pure line-protocol session (RefGo, SLCAN) and the shared TCP adapter
// (protocols/line/net/line_server.hpp).
//
// Contract (single-threaded, event-loop thread only):
// - The adapter hands every received chunk to receive(); the session executes what it can and
//   queues reply bytes, which the adapter collects with take_output() after each call and after
//   every wake-up. A reply must be queued as one contiguous unit (refgo.md §3.3).
// - Output that arises later (a Store completing, a CAN frame from the node) is queued by the
//   session itself, which then calls the `wake` callback given by set_wake(); the adapter collects
//   and writes it.
// - peer_closed(): the client sent FIN. The session still answers the complete lines it has
//   (possibly later, after a pending Store), discards the unterminated rest, and reports
//   finished() once nothing is left to answer; the adapter then flushes and closes.
// - A session never throws on input; malformed input gets the protocol's own error reply.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace mcemu::line {

class StreamSession {
 public:
  virtual ~StreamSession() = default;
  virtual void receive(std::string_view bytes) = 0;
  virtual std::string take_output() = 0;
  virtual void peer_closed() = 0;
  virtual bool finished() const = 0;
  // true: the adapter must stop reading (e.g. waiting for a Store so that replies stay in order).
  virtual bool paused() const { return false; }
  // The adapter is about to close the connection on its own ("queue overflow", "idle timeout"),
  // for the trace (slcan-canopen.md §11.2); the session is destroyed after it.
  virtual void closing(std::string_view /*reason*/) {}
  void set_wake(std::function<void()> wake) { wake_ = std::move(wake); }

 protected:
  void wake() const {
    if (wake_) wake_();
  }

 private:
  std::function<void()> wake_;
};

}  // namespace mcemu::line
