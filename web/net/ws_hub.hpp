// The fan-out of the WebSocket `/api/v1/ws` (web.md §10): owns the 50 ms wall-clock period and the
// list of open WebSocket clients. Each period it asks the `status` source once when any client
// subscribes to status and shares the one immutable message with all of them (§10.5), likewise the
// `scope` source; trace events fed through on_trace() are batched and sent once per period, one
// message per distinct channel filter; publish_udp() sends at once. The period timer runs only while a
// client subscribes to status, scope or trace: an idle hub costs nothing.
//
// The sources are plain functions the composition root wires to the drive's snapshot, scope and
// trace JSON; an unset source sends nothing of its kind. Threading: the io_context's single thread;
// sources are called on it. The hub does not own the clients (ws_session.cpp does: they attach once
// their hello is queued and detach when they begin to close).
#pragma once

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "base/liveness.hpp"
#include "trace/trace.hpp"
#include "web/api/ws_outbox.hpp"
#include "web/api/ws_protocol.hpp"

namespace mcemu::web::net {

struct WsOptions {
  std::size_t max_clients = 16;                              // a further handshake is answered 503 (§10.5)
  std::chrono::milliseconds period{50};                      // status/scope/trace period (§10.3)
  std::chrono::milliseconds ping_interval{10'000};           // §10.4
  std::chrono::milliseconds pong_timeout{30'000};            // close (1001) after this long without a pong
  std::chrono::milliseconds close_timeout{5'000};            // opening/closing handshake; then TCP is closed
  std::size_t queue_limit = api::WsOutbox::k_default_limit;  // unsent scope/trace/udp bytes → 1008
  std::size_t max_message = 64 * 1024;                       // largest client message; larger → close 1009
  std::size_t max_trace_batch = 10'000;                      // trace events kept per period; more are dropped
};

struct WsSources {
  // The §8.1 info object as JSON text, for the hello message.
  std::function<std::string()> info;
  // The complete status message (the §8.2 snapshot with "type":"status"); "" = none this period.
  std::function<std::string()> status;
  // The complete scope message with the samples since the previous call; "" = no new samples.
  std::function<std::string()> scope;
  // The complete trace message ({"type":"trace","events":[…]}) for `events`, which are the events of
  // one period that match `channels` (never empty); "" = send nothing.
  std::function<std::string(std::span<const trace::Event> events, trace::ChannelSet channels)> trace_message;
};

// What the hub needs of an open WebSocket connection.
class WsClient {
 public:
  virtual const api::Subscription& subscription() const = 0;
  virtual void send_status(const api::WsOutbox::Message& message) = 0;  // newest wins
  virtual void send(const api::WsOutbox::Message& message) = 0;         // queued, 1008 on overflow

 protected:
  ~WsClient() = default;
};

class WsHub {
 public:
  explicit WsHub(boost::asio::io_context& io, WsOptions options = {});
  ~WsHub();
  WsHub(const WsHub&) = delete;
  WsHub& operator=(const WsHub&) = delete;

  void set_sources(WsSources sources) { sources_ = std::move(sources); }
  const WsOptions& options() const { return options_; }

  // A trace event as it is recorded (trace::Ring's listener). Returns at once when no client
  // subscribes to trace.
  void on_trace(const trace::Event& event);
  // A console message (udp-debug.md §6), sent at once to the udp subscribers.
  void publish_udp(std::string_view text);

  std::size_t client_count() const { return clients_.size(); }
  std::size_t subscriber_count(api::Topic topic) const;
  std::uint64_t trace_dropped() const { return trace_dropped_; }

  // For the sessions.
  std::string hello_message() const;
  void attach(WsClient& client);
  void detach(WsClient& client);
  void subscription_changed();

  // One period: status, scope, trace batch. The timer calls it; public for tests.
  void tick();
  void stop();

 private:
  bool needs_period() const;
  void recount();
  void arm();

  boost::asio::steady_timer timer_;
  WsOptions options_;
  WsSources sources_;
  std::vector<WsClient*> clients_;
  std::array<std::size_t, api::k_topic_count> subscribers_{};
  std::vector<trace::Event> pending_trace_;
  std::uint64_t trace_dropped_ = 0;
  bool timer_running_ = false;
  bool stopped_ = false;
  std::chrono::steady_clock::time_point next_tick_{};
  base::LivenessToken alive_;  // handlers check it: the hub may be gone
};

}  // namespace mcemu::web::net
