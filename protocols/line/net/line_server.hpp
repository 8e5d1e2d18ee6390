// The one TCP adapter of the line-oriented protocols (RefGo on 10001, SLCAN on 15001).
//
// Owns the listening socket and every connection; each connection drives one pure
// line::StreamSession made by the factory: read (≤ read_chunk bytes) → session.receive → write
// what the session queued. Rules (refgo.md §1, slcan-canopen.md §3.1, design.md):
// - at most max_clients connections; one more is accepted and closed at once without a byte sent,
//   with one warning naming the limit and the flag;
// - TCP_NODELAY, keepalive 10 s / 5 s / 3 probes and TCP_USER_TIMEOUT 25 s on every connection;
// - after the peer's FIN the session answers the complete lines it has, then the connection is
//   shut down after the last byte is written; EPIPE/ECONNRESET are ordinary disconnects;
// - bounded output: above pause_above unsent bytes reading stops until the backlog is below
//   resume_below (RefGo), or — with close_on_overflow — the connection is closed (SLCAN);
// - with idle_timeout, a connection that sent nothing for that long is closed (--idle-timeout).
// The per-connection logic is line_connection.hpp. Threading: the io_context's single thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "base/liveness.hpp"
#include "protocols/line/net/line_connection.hpp"
#include "protocols/line/net/tcp_types.hpp"
#include "protocols/line/stream_session.hpp"

namespace mcemu::line::net {

using SessionFactory = std::function<std::unique_ptr<StreamSession>(const PeerInfo&)>;

class LineServer {
 public:
  // Binds and listens at once; throws boost::system::system_error when the port cannot be bound
  // (the composition root turns it into the one-line start-up error naming the flag).
  LineServer(boost::asio::io_context& io, const boost::asio::ip::tcp::endpoint& endpoint, LineServerOptions options,
             SessionFactory factory);
  ~LineServer();
  LineServer(const LineServer&) = delete;
  LineServer& operator=(const LineServer&) = delete;

  std::uint16_t port() const;
  void start();              // begin accepting
  void stop();               // stop accepting and close every connection
  void close_connections();  // close every connection, keep listening (power cycle)
  std::size_t connection_count() const { return connections_.size(); }
  const LineServerOptions& options() const { return options_; }

 private:
  using Connection = LineConnection<TcpSocket>;
  void do_accept();
  void on_accept(const boost::system::error_code& ec, TcpSocket socket);

  TcpAcceptor acceptor_;
  LineServerOptions options_;
  SessionFactory factory_;
  std::map<LineConnectionBase*, std::shared_ptr<Connection>> connections_;
  std::shared_ptr<base::ConnectionIds> ids_;  // options_.ids, or its own
  bool accepting_ = false;
  base::LivenessToken alive_;  // accept handlers check it: the server may be gone
};

// Socket options of refgo.md §1.3 (also used by SLCAN); exposed for tests.
void apply_stream_socket_options(int fd);
template <class Socket>
void apply_stream_socket_options(Socket& socket) {
  apply_stream_socket_options(socket.native_handle());
}

}  // namespace mcemu::line::net
