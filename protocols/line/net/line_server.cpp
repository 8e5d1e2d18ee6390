#include "protocols/line/net/line_server.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>

namespace mcemu::line::net {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

void apply_stream_socket_options(int fd) {
  const int on = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
  ::setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &on, sizeof on);
  const int idle = 10;
  const int interval = 5;
  const int count = 3;
  const unsigned user_timeout_ms = 25000;
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle, sizeof idle);
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval, sizeof interval);
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &count, sizeof count);
  ::setsockopt(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, &user_timeout_ms, sizeof user_timeout_ms);
}

LineServer::LineServer(asio::io_context& io, const tcp::endpoint& endpoint, LineServerOptions options,
                       SessionFactory factory)
    : acceptor_(io),
      options_(std::move(options)),
      factory_(std::move(factory)),
      ids_(base::own_ids_unless(options_.ids)) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen();
}

LineServer::~LineServer() { stop(); }

std::uint16_t LineServer::port() const { return acceptor_.local_endpoint().port(); }

void LineServer::start() {
  if (accepting_) return;
  accepting_ = true;
  do_accept();
}

void LineServer::stop() {
  accepting_ = false;
  boost::system::error_code ec;
  acceptor_.close(ec);
  close_connections();
}

void LineServer::close_connections() {
  auto all = connections_;  // close() erases from the map
  for (const auto& [key, c] : all) c->close();
}

void LineServer::do_accept() {
  if (!accepting_) return;
  // The completion may come after the server is gone (an accept that completed just before stop(),
  // its handler still queued): it checks first.
  acceptor_.async_accept([this, alive = alive_.watch()](const boost::system::error_code& ec, TcpSocket socket) {
    if (alive) on_accept(ec, std::move(socket));
  });
}

void LineServer::on_accept(const boost::system::error_code& ec, TcpSocket socket) {
  if (!accepting_ || ec == asio::error::operation_aborted) return;
  if (!ec) {
    boost::system::error_code pe;
    const auto remote = socket.remote_endpoint(pe);
    PeerInfo peer{pe ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port()),
                  ids_->next()};
    if (connections_.size() >= options_.max_clients) {
      spdlog::warn("{}: connection limit {} reached ({} sets it); closing connection from {}", options_.name,
                   options_.max_clients, options_.max_clients_flag, peer.address);
      boost::system::error_code ignore;
      socket.close(ignore);
    } else {
      apply_stream_socket_options(socket);
      spdlog::debug("{}: connection from {}", options_.name, peer.address);
      auto c = std::make_shared<Connection>(std::move(socket), options_, peer,
                                            [this](LineConnectionBase* gone) { connections_.erase(gone); });
      connections_.emplace(c.get(), c);
      c->start(factory_(peer));
    }
  } else {
    spdlog::warn("{}: accept failed: {}", options_.name, ec.message());
  }
  do_accept();
}

}  // namespace mcemu::line::net
