// One WebSocket connection of `/api/v1/ws` (web.md §10), taken over from an HttpSession after the
// upgrade request was checked: accept (no extensions), hello, then the read loop (client messages →
// subscription), the write loop over the client's api::WsOutbox, and the ping timer (ping every
// ws.ping_interval, close 1001 after ws.pong_timeout without a pong; the pongs are seen by Beast's
// control callback while the read is pending). A full outbox closes with 1008; a client message over
// ws.max_message closes with 1009. Every close is bounded by ws.close_timeout, after which the TCP
// connection is closed. Internal to web/net. Threading: the io_context's single thread.
#pragma once

#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <chrono>
#include <memory>
#include <string>

#include "web/api/ws_outbox.hpp"
#include "web/api/ws_protocol.hpp"
#include "web/net/connection.hpp"
#include "web/net/stream.hpp"
#include "web/net/ws_hub.hpp"

namespace mcemu::web::net {

class HttpServer;

class WsSession final : public Connection, public WsClient, public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(HttpServer& server, Stream stream, std::uint64_t id, std::string peer);
  ~WsSession() override;
  void start(boost::beast::http::request<boost::beast::http::string_body> request, std::string method,
             std::string target);
  void close() override;

  const api::Subscription& subscription() const override { return subscription_; }
  void send_status(const api::WsOutbox::Message& message) override;
  void send(const api::WsOutbox::Message& message) override;

 private:
  using clock = std::chrono::steady_clock;

  void on_accept(const boost::system::error_code& ec);
  void do_read();
  void on_read(const boost::system::error_code& ec);
  void do_write();
  void arm_ping_timer();
  void on_ping_timer();
  void begin_close(boost::beast::websocket::close_code code, const char* reason);

  HttpServer& server_;
  boost::beast::websocket::stream<Stream> ws_;
  boost::beast::flat_buffer read_buffer_;
  api::WsOutbox outbox_;
  api::Subscription subscription_;
  boost::asio::steady_timer ping_timer_;
  boost::asio::steady_timer close_timer_;
  clock::time_point last_pong_{};
  clock::time_point next_ping_{};
  std::uint64_t id_;
  std::string peer_;
  std::string method_;
  std::string target_;
  bool open_ = false;
  bool attached_ = false;
  bool writing_ = false;
  bool pinging_ = false;
  bool closing_ = false;
  bool closed_ = false;
};

}  // namespace mcemu::web::net
