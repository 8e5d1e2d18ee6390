#include "web/net/http_server.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/steady_timer.hpp>

#include "protocols/line/net/line_server.hpp"
#include "web/net/http_session.hpp"

namespace mcemu::web::net {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using error_code = boost::system::error_code;

HttpServer::HttpServer(asio::io_context& io, const tcp::endpoint& endpoint, HttpOptions options, Handler handler)
    : acceptor_(io),
      options_(options),
      handler_(std::move(handler)),
      hub_(io, options.ws),
      ids_(base::own_ids_unless(options_.ids)) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen();
}

HttpServer::~HttpServer() { stop(); }

std::uint16_t HttpServer::port() const { return acceptor_.local_endpoint().port(); }

void HttpServer::start() {
  if (accepting_) return;
  accepting_ = true;
  do_accept();
}

void HttpServer::stop() {
  accepting_ = false;
  error_code ec;
  acceptor_.close(ec);
  hub_.stop();
  auto all = connections_;  // close() erases from connections_
  for (const auto& [raw, c] : all) c->close();
}

void HttpServer::do_accept() {
  if (!accepting_) return;
  acceptor_.async_accept([this, alive = alive_.watch()](const error_code& ec, Socket socket) {
    if (!alive || !accepting_ || ec == asio::error::operation_aborted) return;
    if (ec) {
      // Out of descriptors and the like: retry a little later instead of spinning.
      spdlog::warn("http: accept failed: {}", ec.message());
      auto retry = std::make_shared<asio::steady_timer>(acceptor_.get_executor(), std::chrono::milliseconds(100));
      retry->async_wait([this, retry, alive](const error_code&) {
        if (alive) do_accept();
      });
      return;
    }
    error_code pe;
    const auto remote = socket.remote_endpoint(pe);
    const std::string peer = pe ? std::string("?") : remote.address().to_string() + ":" + std::to_string(remote.port());
    if (connections_.size() >= options_.max_clients) {
      spdlog::warn("http: connection limit {} reached (--max-clients sets it); closing connection from {}",
                   options_.max_clients, peer);
      socket.close(pe);
    } else {
      line::net::apply_stream_socket_options(socket);
      auto s = std::make_shared<HttpSession>(*this, std::move(socket), ids_->next(), peer);
      adopt(s);
      s->start();
    }
    do_accept();
  });
}

}  // namespace mcemu::web::net
