#include "protocols/line/net/line_server.hpp"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>

#include <array>
#include <boost/asio/write.hpp>

namespace mcemu::line::net {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

void apply_stream_socket_options(tcp::socket& socket) {
  boost::system::error_code ec;
  socket.set_option(tcp::no_delay(true), ec);
  socket.set_option(asio::socket_base::keep_alive(true), ec);
  const int fd = socket.native_handle();
  const int idle = 10;
  const int interval = 5;
  const int count = 3;
  const unsigned user_timeout_ms = 25000;
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle, sizeof idle);
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval, sizeof interval);
  ::setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &count, sizeof count);
  ::setsockopt(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, &user_timeout_ms, sizeof user_timeout_ms);
}

// One accepted connection: read loop, session, write queue. Lives in LineServer::connections_
// until it closes; async handlers hold a shared_ptr.
class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(LineServer& server, tcp::socket socket, PeerInfo peer)
      : server_(server), socket_(std::move(socket)), peer_(std::move(peer)), buffer_(server.options_.read_chunk) {}

  void start(std::unique_ptr<StreamSession> session) {
    session_ = std::move(session);
    std::weak_ptr<Connection> weak = shared_from_this();
    session_->set_wake([weak] {
      if (auto self = weak.lock()) self->on_session_output();
    });
    do_read();
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_both, ec);
    socket_.close(ec);
    if (session_) session_->set_wake({});
    server_.forget(shared_from_this());
  }

 private:
  std::size_t backlog() const { return pending_.size() + in_flight_.size(); }

  bool may_read() const {
    if (closed_ || reading_ || peer_eof_ || session_->paused()) return false;
    return !read_paused_for_backlog_;
  }

  void do_read() {
    if (!may_read()) return;
    reading_ = true;
    socket_.async_read_some(asio::buffer(buffer_),
                            [self = shared_from_this()](auto ec, std::size_t n) { self->on_read(ec, n); });
  }

  void on_read(const boost::system::error_code& ec, std::size_t n) {
    reading_ = false;
    if (closed_) return;
    if (ec == asio::error::eof) {
      peer_eof_ = true;
      session_->peer_closed();
      collect();
      return;
    }
    if (ec) {
      spdlog::debug("{}: {} disconnected ({})", server_.options_.name, peer_.address, ec.message());
      close();
      return;
    }
    session_->receive(std::string_view(buffer_.data(), n));
    collect();
    do_read();
  }

  void on_session_output() {
    if (closed_) return;
    collect();
    do_read();
  }

  // Moves the session's output into the write queue, applies the backlog policy, starts a write
  // and closes a finished session once everything is written.
  void collect() {
    if (closed_) return;
    pending_ += session_->take_output();
    const auto& o = server_.options_;
    if (backlog() > o.pause_above) {
      if (o.close_on_overflow) {
        spdlog::warn("{}: closing {}: output queue above {} bytes (client does not read)", o.name, peer_.address,
                     o.pause_above);
        close();
        return;
      }
      read_paused_for_backlog_ = true;
    }
    do_write();
    maybe_finish();
  }

  void do_write() {
    if (writing_ || pending_.empty() || closed_) return;
    writing_ = true;
    in_flight_.swap(pending_);
    asio::async_write(socket_, asio::buffer(in_flight_),
                      [self = shared_from_this()](auto ec, std::size_t) { self->on_write(ec); });
  }

  void on_write(const boost::system::error_code& ec) {
    writing_ = false;
    in_flight_.clear();
    if (closed_) return;
    if (ec) {
      spdlog::debug("{}: {} disconnected while writing ({})", server_.options_.name, peer_.address, ec.message());
      close();
      return;
    }
    if (read_paused_for_backlog_ && backlog() < server_.options_.resume_below) read_paused_for_backlog_ = false;
    do_write();
    maybe_finish();
    do_read();
  }

  void maybe_finish() {
    if (closed_ || !peer_eof_ || !session_->finished() || writing_ || !pending_.empty()) return;
    boost::system::error_code ec;
    socket_.shutdown(tcp::socket::shutdown_send, ec);
    close();
  }

  LineServer& server_;
  tcp::socket socket_;
  PeerInfo peer_;
  std::unique_ptr<StreamSession> session_;
  std::vector<char> buffer_;
  std::string pending_;
  std::string in_flight_;
  bool reading_ = false;
  bool writing_ = false;
  bool peer_eof_ = false;
  bool closed_ = false;
  bool read_paused_for_backlog_ = false;
};

LineServer::LineServer(asio::io_context& io, const tcp::endpoint& endpoint, LineServerOptions options,
                       SessionFactory factory)
    : acceptor_(io), options_(std::move(options)), factory_(std::move(factory)) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
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
  auto all = connections_;  // close() erases from the set
  for (const auto& c : all) c->close();
}

void LineServer::forget(const std::shared_ptr<Connection>& c) { connections_.erase(c); }

void LineServer::do_accept() {
  if (!accepting_) return;
  acceptor_.async_accept(
      [this](const boost::system::error_code& ec, tcp::socket socket) { on_accept(ec, std::move(socket)); });
}

void LineServer::on_accept(const boost::system::error_code& ec, tcp::socket socket) {
  if (!accepting_ || ec == asio::error::operation_aborted) return;
  if (!ec) {
    boost::system::error_code pe;
    const auto remote = socket.remote_endpoint(pe);
    PeerInfo peer{pe ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port()),
                  next_id_++};
    if (connections_.size() >= options_.max_clients) {
      spdlog::warn("{}: connection limit {} reached ({} sets it); closing connection from {}", options_.name,
                   options_.max_clients, options_.max_clients_flag, peer.address);
      boost::system::error_code ignore;
      socket.close(ignore);
    } else {
      apply_stream_socket_options(socket);
      spdlog::debug("{}: connection from {}", options_.name, peer.address);
      auto c = std::make_shared<Connection>(*this, std::move(socket), peer);
      connections_.insert(c);
      c->start(factory_(peer));
    }
  } else {
    spdlog::warn("{}: accept failed: {}", options_.name, ec.message());
  }
  do_accept();
}

}  // namespace mcemu::line::net
