#include "web/net/http_server.hpp"

#include <spdlog/spdlog.h>

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <optional>

namespace mcemu::web::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(HttpServer& server, tcp::socket socket) : server_(server), stream_(std::move(socket)) {}

  void start() { do_read(); }

  void close() {
    if (closed_) return;
    closed_ = true;
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.socket().close(ec);
    server_.forget(shared_from_this());
  }

 private:
  void do_read() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(server_.options_.header_limit));
    parser_->body_limit(server_.options_.body_limit);
    stream_.expires_after(server_.options_.idle_timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    if (closed_) return;
    if (ec == http::error::end_of_stream || ec == beast::error::timeout || ec == asio::error::operation_aborted ||
        ec == asio::error::connection_reset || ec == asio::error::eof) {
      close();
      return;
    }
    if (ec == http::error::header_limit) return reply_error(431, "request header fields too large");
    if (ec == http::error::body_limit) return reply_error(413, "request body too large");
    if (ec) return reply_error(400, "malformed request: " + ec.message());

    const auto& req = parser_->get();
    api::Request r;
    r.method = std::string(req.method_string());
    r.target = std::string(req.target());
    if (auto it = req.find(http::field::content_type); it != req.end()) r.content_type = std::string(it->value());
    r.body = req.body();
    const bool keep_alive = req.keep_alive();
    const bool head = req.method() == http::verb::head;
    const unsigned version = req.version();
    server_.handler_(r, [self = shared_from_this(), keep_alive, head, version](api::Response out) {
      if (!self->closed_) self->write(std::move(out), keep_alive, head, version);
    });
  }

  void reply_error(int status, const std::string& reason) { write(api::error_page(status, reason), false, false, 11); }

  void write(api::Response out, bool keep_alive, bool head, unsigned version) {
    auto res = std::make_shared<http::response<http::string_body>>(static_cast<http::status>(out.status), version);
    res->set(http::field::server, "mcemu");
    res->set(http::field::content_type, out.content_type);
    for (const auto& [k, v] : out.headers) res->set(k, v);
    res->keep_alive(keep_alive);
    const std::size_t length = out.body.size();
    if (!head) res->body() = std::move(out.body);
    res->content_length(length);
    stream_.expires_after(server_.options_.idle_timeout);
    http::async_write(stream_, *res, [self = shared_from_this(), res, keep_alive](beast::error_code ec, std::size_t) {
      if (ec || !keep_alive) {
        self->close();
        return;
      }
      self->do_read();
    });
  }

  HttpServer& server_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  bool closed_ = false;
};

HttpServer::HttpServer(asio::io_context& io, const tcp::endpoint& endpoint, HttpOptions options, Handler handler)
    : acceptor_(io), options_(options), handler_(std::move(handler)) {
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
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
  beast::error_code ec;
  acceptor_.close(ec);
  auto all = sessions_;
  for (const auto& s : all) s->close();
}

void HttpServer::do_accept() {
  if (!accepting_) return;
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!accepting_ || ec == asio::error::operation_aborted) return;
    if (!ec) {
      if (sessions_.size() >= options_.max_clients) {
        beast::error_code pe;
        const auto remote = socket.remote_endpoint(pe);
        spdlog::warn("http: connection limit {} reached (--max-clients sets it); closing connection from {}",
                     options_.max_clients, pe ? std::string("?") : remote.address().to_string());
        socket.close(pe);
      } else {
        socket.set_option(tcp::no_delay(true), ec);
        auto s = std::make_shared<HttpSession>(*this, std::move(socket));
        sessions_.insert(s);
        s->start();
      }
    }
    do_accept();
  });
}

}  // namespace mcemu::web::net
