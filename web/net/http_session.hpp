// One HTTP/1.1 connection of HttpServer (the contract is in http_server.hpp): read header → decide
// → (100 Continue) → read body → handler → write → next request, each step with its deadline.
// Internal to web/net. Threading: the io_context's single thread.
#pragma once

#include <array>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/string_body.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "web/api/http_types.hpp"
#include "web/net/connection.hpp"

namespace mcemu::web::net {

class HttpServer;

class HttpSession final : public Connection, public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(HttpServer& server, boost::asio::ip::tcp::socket socket, std::uint64_t id, std::string peer);
  void start();
  void close() override;

 private:
  using Parser = boost::beast::http::request_parser<boost::beast::http::string_body>;

  void do_read_header();
  void on_header(const boost::system::error_code& ec);
  void do_read_body();
  void on_body(const boost::system::error_code& ec);
  void on_read_error(const boost::system::error_code& ec);
  void on_request();
  void on_websocket_request(const api::Request& request);
  void send(api::Response response, bool keep_alive);
  void fail(int status, const std::string& reason);
  void linger();
  void do_discard();
  // The session's one deadline (idle, body, write or linger): a time point, and a timer that is
  // re-armed only when the deadline moves before its expiry or when it fires early. A deadline
  // that passes closes the socket; the pending read or write then ends with operation_aborted.
  // (beast::tcp_stream's own timeouts cancel and re-arm a read and a write timer for every request:
  // a handler run per cancel and a timerfd_settime whenever the earliest deadline of the loop
  // changes — issue 26, the API at the socket's speed.)
  void arm(std::chrono::steady_clock::duration timeout);
  void disarm() { deadline_ = std::chrono::steady_clock::time_point::max(); }
  void wait_for(std::chrono::steady_clock::time_point t);
  void on_deadline();

  HttpServer& server_;
  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::optional<Parser> parser_;
  std::uint64_t id_;
  std::string peer_;
  // The request being answered: for the observer and the response's version and HEAD rule.
  std::string method_;
  std::string target_;
  unsigned version_ = 11;
  bool head_ = false;
  bool polling_ = false;             // the request carried k_poll_header
  std::shared_ptr<void> in_flight_;  // the 100 Continue being written
  // The response being written: status line and fields (kept for its capacity), and the body.
  std::string out_head_;
  std::string out_body_;
  std::array<char, 4096> discard_{};
  bool closed_ = false;
  bool handed_over_ = false;  // the socket now belongs to a WsSession
  boost::asio::steady_timer timer_;
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
  std::uint64_t wait_serial_ = 0;  // the timer's current wait; a cancelled one's handler sees another
  bool waiting_ = false;           // a wait is pending
};

}  // namespace mcemu::web::net
