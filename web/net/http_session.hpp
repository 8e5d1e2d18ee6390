// One HTTP/1.1 connection of HttpServer (the contract is in http_server.hpp): read header → decide
// → (100 Continue) → read body → handler → write → next request, each step with its deadline.
// Internal to web/net. Threading: the io_context's single thread.
#pragma once

#include <array>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/string_body.hpp>
#include <memory>
#include <optional>
#include <string>

#include "web/api/http_types.hpp"
#include "web/net/connection.hpp"
#include "web/net/stream.hpp"

namespace mcemu::web::net {

class HttpServer;

class HttpSession final : public Connection, public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(HttpServer& server, Socket socket, std::uint64_t id, std::string peer);
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

  HttpServer& server_;
  Stream stream_;
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
};

}  // namespace mcemu::web::net
