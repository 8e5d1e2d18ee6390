#include "web/net/ws_session.hpp"

#include <spdlog/spdlog.h>

#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/http/field.hpp>

#include "web/net/http_server.hpp"

namespace mcemu::web::net {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using error_code = boost::system::error_code;

WsSession::WsSession(HttpServer& server, Stream stream, std::uint64_t id, std::string peer)
    : server_(server),
      ws_(std::move(stream)),
      outbox_(server.options_.ws.queue_limit),
      ping_timer_(ws_.get_executor()),
      close_timer_(ws_.get_executor()),
      id_(id),
      peer_(std::move(peer)) {
  ++server_.websockets_;
}

WsSession::~WsSession() = default;

void WsSession::start(http::request<http::string_body> request, std::string method, std::string target) {
  method_ = std::move(method);
  target_ = std::move(target);
  const auto& o = server_.options_.ws;
  // The WebSocket has its own deadlines; the HTTP ones must not close it (Beast's rule for basic_stream).
  beast::get_lowest_layer(ws_).expires_never();
  websocket::stream_base::timeout t{};
  t.handshake_timeout = o.close_timeout;
  t.idle_timeout = websocket::stream_base::none();
  t.keep_alive_pings = false;
  ws_.set_option(t);
  ws_.set_option(
      websocket::stream_base::decorator([](websocket::response_type& res) { res.set(http::field::server, "mcemu"); }));
  ws_.read_message_max(o.max_message);
  ws_.control_callback([this](websocket::frame_type kind, beast::string_view) {
    if (kind == websocket::frame_type::pong) last_pong_ = clock::now();
  });
  ws_.async_accept(request, [self = shared_from_this()](const error_code& ec) { self->on_accept(ec); });
}

void WsSession::on_accept(const error_code& ec) {
  if (closed_) return;
  if (ec) {
    spdlog::debug("http: WebSocket handshake with {} failed: {}", peer_, ec.message());
    return close();
  }
  open_ = true;
  if (server_.observer_.answered) server_.observer_.answered({id_, peer_, method_, target_, 101});
  WsHub& hub = server_.hub_;
  (void)outbox_.push(std::make_shared<const std::string>(hub.hello_message()));
  attached_ = true;
  hub.attach(*this);
  last_pong_ = clock::now();
  next_ping_ = last_pong_ + server_.options_.ws.ping_interval;
  arm_ping_timer();
  do_write();
  do_read();
}

void WsSession::send_status(const api::WsOutbox::Message& message) {
  if (!open_ || closing_) return;
  outbox_.push_status(message);
  do_write();
}

void WsSession::send(const api::WsOutbox::Message& message) {
  if (!open_ || closing_) return;
  if (!outbox_.push(message)) {
    spdlog::warn("http: WebSocket client {} does not keep up ({} bytes queued); closing it (1008)", peer_,
                 outbox_.queued_bytes());
    return begin_close(websocket::close_code::policy_error, "send queue limit");
  }
  do_write();
}

void WsSession::do_write() {
  if (writing_ || closing_ || closed_) return;
  auto message = outbox_.pop();
  if (!message) return;
  writing_ = true;
  ws_.text(true);
  ws_.async_write(asio::buffer(*message), [self = shared_from_this(), message](const error_code& ec, std::size_t) {
    self->writing_ = false;
    if (self->closed_) return;
    if (ec) return self->close();
    self->do_write();
  });
}

void WsSession::do_read() {
  ws_.async_read(read_buffer_, [self = shared_from_this()](const error_code& ec, std::size_t) { self->on_read(ec); });
}

void WsSession::on_read(const error_code& ec) {
  if (closed_) return;
  if (ec) {
    // error::closed: the closing handshake is complete; message_too_big: Beast has sent 1009.
    if (ec != websocket::error::closed) spdlog::debug("http: WebSocket {} read: {}", peer_, ec.message());
    return close();
  }
  if (ws_.got_text() && !closing_) {
    const std::string text = beast::buffers_to_string(read_buffer_.data());
    if (api::apply_client_message(subscription_, text)) server_.hub_.subscription_changed();
  }
  read_buffer_.consume(read_buffer_.size());
  do_read();
}

void WsSession::arm_ping_timer() {
  const auto& o = server_.options_.ws;
  ping_timer_.expires_at(std::min(next_ping_, last_pong_ + o.pong_timeout));
  ping_timer_.async_wait([self = shared_from_this()](const error_code& ec) {
    if (ec || self->closed_ || self->closing_) return;
    self->on_ping_timer();
  });
}

void WsSession::on_ping_timer() {
  const auto& o = server_.options_.ws;
  const auto now = clock::now();
  if (now - last_pong_ >= o.pong_timeout) {
    spdlog::info("http: WebSocket client {} sent no pong for {} ms; closing it", peer_, o.pong_timeout.count());
    return begin_close(websocket::close_code::going_away, "no pong");
  }
  if (now >= next_ping_) {
    if (!pinging_) {
      pinging_ = true;
      ws_.async_ping({}, [self = shared_from_this()](const error_code& ec) {
        self->pinging_ = false;
        if (!ec || self->closed_) return;
        if (ec != asio::error::operation_aborted) self->close();
      });
    }
    next_ping_ = now + o.ping_interval;
  }
  arm_ping_timer();
}

void WsSession::begin_close(websocket::close_code code, const char* reason) {
  if (closing_ || closed_) return;
  closing_ = true;
  if (attached_) {
    attached_ = false;
    server_.hub_.detach(*this);
  }
  ping_timer_.cancel();
  close_timer_.expires_after(server_.options_.ws.close_timeout);
  close_timer_.async_wait([self = shared_from_this()](const error_code& ec) {
    if (!ec) self->close();
  });
  // The pending read sees the peer's answering close frame (error::closed) and ends the session.
  ws_.async_close(websocket::close_reason(code, reason), [self = shared_from_this()](const error_code& ec) {
    if (ec && !self->closed_) self->close();
  });
}

void WsSession::close() {
  if (closed_) return;
  closed_ = true;
  const auto self = shared_from_this();  // forget() may drop the last other reference
  if (attached_) {
    attached_ = false;
    server_.hub_.detach(*this);
  }
  ping_timer_.cancel();
  close_timer_.cancel();
  error_code ec;
  auto& socket = beast::get_lowest_layer(ws_).socket();
  socket.shutdown(asio::ip::tcp::socket::shutdown_both, ec);
  socket.close(ec);
  --server_.websockets_;
  if (server_.observer_.closed) server_.observer_.closed(id_);
  server_.forget(this);
}

}  // namespace mcemu::web::net
