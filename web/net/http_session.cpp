#include "web/net/http_session.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/write.hpp>
#include <boost/beast/core/string.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <cctype>

#include "web/api/origin.hpp"
#include "web/api/router.hpp"
#include "web/net/http_server.hpp"
#include "web/net/ws_session.hpp"

namespace mcemu::web::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using error_code = boost::system::error_code;

namespace {

constexpr std::string_view k_ws_path = "/api/v1/ws";

bool is_disconnect(const error_code& ec) {
  return ec == http::error::end_of_stream || ec == beast::error::timeout || ec == asio::error::operation_aborted ||
         ec == asio::error::connection_reset || ec == asio::error::eof || ec == asio::error::broken_pipe ||
         ec == asio::error::not_connected || ec == asio::error::bad_descriptor;
}

// RFC 6455 §4.2.1: GET, HTTP/1.1, Connection: upgrade, Upgrade: websocket, a 16-byte key in
// base64 (24 characters) and version 13. Anything else to /api/v1/ws is answered 426.
bool is_valid_upgrade(const http::request<http::string_body>& req) {
  if (!beast::websocket::is_upgrade(req)) return false;
  const auto version = req[http::field::sec_websocket_version];
  const auto key = req[http::field::sec_websocket_key];
  if (version != "13" || key.size() != 24) return false;
  for (std::size_t i = 0; i < key.size(); ++i) {
    const auto c = static_cast<unsigned char>(key[i]);
    const bool pad = c == '=' && i >= 22;
    if (!std::isalnum(c) && c != '+' && c != '/' && !pad) return false;
  }
  return true;
}

bool has_no_body(int status) { return (status >= 100 && status < 200) || status == 204 || status == 304; }

// "Name: value\r\n"; a CR or LF inside (never from our handlers) becomes a space, so that no value
// can end the field or the header early.
void append_field(std::string& out, std::string_view name, std::string_view value) {
  const auto clean = [&out](std::string_view text) {
    for (const char c : text) out.push_back(c == '\r' || c == '\n' ? ' ' : c);
  };
  clean(name);
  out.append(": ");
  clean(value);
  out.append("\r\n");
}

}  // namespace

HttpSession::HttpSession(HttpServer& server, Socket socket, std::uint64_t id, std::string peer)
    : server_(server), stream_(std::move(socket)), id_(id), peer_(std::move(peer)) {}

void HttpSession::start() {
  if (server_.observer_.opened) server_.observer_.opened(id_, peer_);
  do_read_header();
}

void HttpSession::close() {
  if (closed_) return;
  closed_ = true;
  const auto self = shared_from_this();  // forget() may drop the last other reference
  if (!handed_over_) {
    error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ec);
    stream_.socket().close(ec);
    if (server_.observer_.closed) server_.observer_.closed(id_);
  }
  server_.forget(this);
}

void HttpSession::do_read_header() {
  parser_.emplace();
  parser_->header_limit(static_cast<std::uint32_t>(server_.options_.header_limit));
  parser_->body_limit(server_.options_.body_limit);
  method_.clear();
  target_.clear();
  version_ = 11;
  head_ = false;
  polling_ = false;
  stream_.expires_after(server_.options_.idle_timeout);
  http::async_read_header(stream_, buffer_, *parser_,
                          [self = shared_from_this()](const error_code& ec, std::size_t) { self->on_header(ec); });
}

void HttpSession::on_header(const error_code& ec) {
  if (closed_) return;
  if (parser_->is_header_done()) {
    const auto& req = parser_->get();
    method_ = std::string(req.method_string());
    target_ = std::string(req.target());
    version_ = req.version() == 10 ? 10 : 11;
    head_ = req.method() == http::verb::head;
    polling_ = req.count(beast::string_view(k_poll_header.data(), k_poll_header.size())) > 0;
  }
  if (ec) return on_read_error(ec);
  if (parser_->is_done()) return on_request();
  if (beast::iequals(parser_->get()[http::field::expect], "100-continue")) {
    auto cont = std::make_shared<http::response<http::empty_body>>(http::status::continue_, version_);
    in_flight_ = cont;
    stream_.expires_after(server_.options_.write_timeout);
    http::async_write(stream_, *cont, [self = shared_from_this()](const error_code& wec, std::size_t) {
      if (self->closed_) return;
      self->in_flight_.reset();
      if (wec) return self->close();
      self->do_read_body();
    });
    return;
  }
  do_read_body();
}

void HttpSession::do_read_body() {
  stream_.expires_after(server_.options_.body_timeout);
  http::async_read(stream_, buffer_, *parser_,
                   [self = shared_from_this()](const error_code& ec, std::size_t) { self->on_body(ec); });
}

void HttpSession::on_body(const error_code& ec) {
  if (closed_) return;
  if (ec) return on_read_error(ec);
  on_request();
}

void HttpSession::on_read_error(const error_code& ec) {
  if (ec == http::error::header_limit) return fail(431, "request header fields too large");
  if (ec == http::error::body_limit) return fail(413, "request body too large");
  // A deadline that passed has closed the socket already (beast::basic_stream); nothing can be sent.
  if (is_disconnect(ec)) return close();
  fail(400, "malformed request: " + ec.message());
}

void HttpSession::on_request() {
  auto& req = parser_->get();
  api::Request r;
  r.method = method_;
  r.target = target_;
  if (const auto it = req.find(http::field::content_type); it != req.end()) r.content_type = std::string(it->value());
  r.body = std::move(req.body());
  for (const auto& field : req) {
    std::string name(field.name_string());
    for (auto& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    r.headers.emplace_back(std::move(name), std::string(field.value()));
  }
  r.conn = id_;
  r.peer = peer_;
  const bool keep_alive = req.keep_alive();

  const std::string_view path = std::string_view(target_).substr(0, target_.find('?'));
  if (path == k_ws_path) return on_websocket_request(r);

  auto answered = std::make_shared<bool>(false);
  auto respond = [self = shared_from_this(), answered, keep_alive](api::Response out) {
    if (*answered) return;
    *answered = true;
    if (!self->closed_) self->send(std::move(out), keep_alive);
  };
  try {
    server_.handler_(r, respond);
  } catch (const std::exception& e) {
    spdlog::error("http: {} {}: {}", method_, target_, e.what());
    if (!*answered) respond(api::error_page(500, "internal error"));
  }
  // A handler that answers later (a Store waits for the disk) has no deadline meanwhile. One that
  // answered already has armed the write's: no timer is cancelled and re-armed in between (each
  // change of a pending deadline costs a handler run through the loop, per request).
  if (!*answered && !closed_) stream_.expires_never();
}

void HttpSession::on_websocket_request(const api::Request& request) {
  const bool keep_alive = parser_->get().keep_alive();
  if (!is_valid_upgrade(parser_->get())) {
    auto r = api::error_page(426, "/api/v1/ws is a WebSocket: send a WebSocket upgrade request (RFC 6455)");
    r.headers.emplace_back("Upgrade", "websocket");
    r.headers.emplace_back("Sec-WebSocket-Version", "13");
    return send(std::move(r), keep_alive);
  }
  if (api::is_cross_site(request)) return send(api::cross_site_refused(), keep_alive);
  if (server_.websockets_ >= server_.options_.ws.max_clients) {
    return send(api::error_page(
                    503, "WebSocket limit reached (" + std::to_string(server_.options_.ws.max_clients) + " clients)"),
                keep_alive);
  }
  handed_over_ = true;
  auto ws = std::make_shared<WsSession>(server_, std::move(stream_), id_, peer_);
  server_.adopt(ws);
  ws->start(parser_->release(), method_, target_);
  close();  // forgets this session; the socket is the WebSocket's now
}

void HttpSession::send(api::Response out, bool keep_alive) {
  keep_alive = keep_alive && !out.close;
  const bool body = !has_no_body(out.status);
  // The status line and fields as Beast's serializer writes them (insertion order; Connection as
  // keep_alive() sets it), formatted into a buffer the session keeps, and the body beside it: one
  // gather write and no allocation per response once the buffers have grown (issue 26: the API at
  // the socket's speed; a Beast response object costs a node per field and a serializer).
  out_head_.clear();
  out_head_.append(version_ == 10 ? "HTTP/1.0 " : "HTTP/1.1 ").append(std::to_string(out.status)).append(" ");
  const auto reason = http::obsolete_reason(static_cast<http::status>(out.status));
  out_head_.append(reason.data(), reason.size()).append("\r\nServer: mcemu\r\n");
  if (!out.content_type.empty() && body) append_field(out_head_, "Content-Type", out.content_type);
  for (const auto& [k, v] : out.headers) append_field(out_head_, k, v);
  if (version_ == 10 && keep_alive) out_head_.append("Connection: keep-alive\r\n");
  if (version_ != 10 && !keep_alive) out_head_.append("Connection: close\r\n");
  // HEAD: the same headers as GET, Content-Length of the GET body, no body (web.md §1.4).
  if (body) out_head_.append("Content-Length: ").append(std::to_string(out.body.size())).append("\r\n");
  out_head_.append("\r\n");
  out_body_.clear();
  if (body && !head_) out_body_.swap(out.body);  // HEAD: no body
  if (server_.observer_.answered) server_.observer_.answered({id_, peer_, method_, target_, out.status, polling_});
  stream_.expires_after(server_.options_.write_timeout);
  const std::array<asio::const_buffer, 2> buffers{asio::buffer(out_head_), asio::buffer(out_body_)};
  asio::async_write(stream_, buffers, [self = shared_from_this(), keep_alive](const error_code& ec, std::size_t) {
    if (self->closed_) return;
    if (ec) return self->close();
    if (!keep_alive) return self->linger();
    self->do_read_header();
  });
}

void HttpSession::fail(int status, const std::string& reason) {
  auto r = api::error_page(status, reason);
  r.close = true;
  send(std::move(r), false);
}

// web.md §1.2: after a closing answer, stop sending but keep reading (and dropping) what the client
// still sends, for up to `linger`, so that it reads the status instead of a connection reset.
void HttpSession::linger() {
  error_code ec;
  stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  if (ec) return close();
  stream_.expires_after(server_.options_.linger);
  do_discard();
}

void HttpSession::do_discard() {
  stream_.async_read_some(asio::buffer(discard_), [self = shared_from_this()](const error_code& ec, std::size_t) {
    if (self->closed_) return;
    if (ec) return self->close();
    self->do_discard();
  });
}

}  // namespace mcemu::web::net
