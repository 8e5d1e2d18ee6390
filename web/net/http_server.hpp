// HTTP/1.1 server of the web UI, the JSON API and the WebSocket `/api/v1/ws` (web.md §1, §10) on the
// shared event loop, built on Boost.Beast. Each request becomes a web::api::Request for the pure
// handler (the router); its answer is written back. Everything is asynchronous on the io_context's
// single thread, with a deadline on every read and write, so a slow or stalled client only ever
// holds its own connection.
//
// Per connection (http_session.cpp): keep-alive; the header is read first (request line + headers
// ≤ header_limit, else 431), then decided (Content-Length > body_limit → 413; malformed → 400;
// `Expect: 100-continue` → `100 Continue`), then the body (chunked or not, ≤ body_limit, else 413).
// A 431, 413 or 400 is sent with `Connection: close`; the sending side is then shut down and input
// discarded for up to `linger` before the socket is closed, so a client still sending reads the
// status. HEAD is answered like GET without the body. Response::close ends the connection.
// `/api/v1/ws` never reaches the handler: a valid upgrade from the same origin becomes a WebSocket
// (ws_session.cpp); not an upgrade → 426, cross-site (api::is_cross_site) → 403, more than
// ws.max_clients WebSockets → 503.
//
// At most max_clients connections, WebSockets included; one more is accepted and closed at once,
// with one warning.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <unordered_map>

#include "base/connection_ids.hpp"
#include "base/liveness.hpp"
#include "web/api/http_types.hpp"
#include "web/net/stream.hpp"
#include "web/net/ws_hub.hpp"

namespace mcemu::web::net {

struct HttpOptions {
  std::size_t max_clients = 32;          // connections incl. WebSockets (web.md §1.1)
  std::size_t header_limit = 8 * 1024;   // request line + headers → 431
  std::size_t body_limit = 1024 * 1024;  // → 413
  // Keep-alive: a connection that does not complete its next request header within this time is
  // closed. 60 s, or the smaller --idle-timeout (the composition root passes the minimum).
  std::chrono::milliseconds idle_timeout{60'000};
  std::chrono::milliseconds body_timeout{60'000};   // to receive a body once its header is in
  std::chrono::milliseconds write_timeout{60'000};  // to send one response to a client that reads
  std::chrono::milliseconds linger{1'000};          // input discarded after a closing error response
  WsOptions ws;
  // The drive's connection ids, shared with its line listeners (base/connection_ids.hpp); empty =
  // this server counts from 1 on its own. A WebSocket keeps the id of its upgrade request.
  std::shared_ptr<base::ConnectionIds> ids;
};

// A request the web pages repeat on a timer carries this header (any value); the observer is told,
// so that the trace can leave the pages' own polling out (web.md §8.6).
inline constexpr std::string_view k_poll_header = "X-Mcemu-Poll";

// Answers one request: must call `respond` exactly once, possibly later, on the loop thread.
using Handler = std::function<void(const api::Request&, api::Respond respond)>;

// What the server tells the composition root (trace `http` channel, LINK/ACT LED of morse-led.md §5).
// Every member may be empty. Called on the loop thread; the string_views are valid during the call only.
struct HttpObserver {
  struct Answer {
    std::uint64_t conn = 0;
    std::string_view peer;    // "127.0.0.1:53422"
    std::string_view method;  // "GET"; empty when the request line could not be read
    std::string_view target;  // "/index.html?x=1"; empty likewise
    int status = 0;           // 101 for an accepted WebSocket upgrade
    bool polling = false;     // the request carried k_poll_header (a page's timer, web.md §8.6)
  };
  std::function<void(std::uint64_t conn, std::string_view peer)> opened;  // connection accepted
  std::function<void(std::uint64_t conn)> closed;                         // its socket closed
  std::function<void(const Answer&)> answered;  // a final response was started (not 100 Continue)
};

class Connection;

class HttpServer {
 public:
  // Binds and listens at once; throws boost::system::system_error when the port cannot be bound.
  HttpServer(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint, HttpOptions options,
             Handler handler);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  std::uint16_t port() const;
  void start();
  void stop();  // stop accepting, close every connection (WebSockets included)

  void set_observer(HttpObserver observer) { observer_ = std::move(observer); }
  // The WebSocket fan-out: set its sources, feed it trace events and UDP console lines.
  WsHub& ws_hub() { return hub_; }

  std::size_t connection_count() const { return connections_.size(); }
  std::size_t websocket_count() const { return websockets_; }
  const HttpOptions& options() const { return options_; }

 private:
  friend class HttpSession;
  friend class WsSession;
  void do_accept();
  void adopt(const std::shared_ptr<Connection>& c) { connections_[c.get()] = c; }
  void forget(Connection* c) { connections_.erase(c); }

  Acceptor acceptor_;
  HttpOptions options_;
  Handler handler_;
  HttpObserver observer_;
  WsHub hub_;
  std::unordered_map<Connection*, std::shared_ptr<Connection>> connections_;
  std::size_t websockets_ = 0;
  std::shared_ptr<base::ConnectionIds> ids_;  // options_.ids, or its own
  bool accepting_ = false;
  base::LivenessToken alive_;  // accept handlers check it
};

}  // namespace mcemu::web::net
