// HTTP/1.1 server of the web UI and JSON API on the shared event loop (web.md §1), built on
// Boost.Beast. It turns each request into a web::api::Request, asks the pure router and writes the
// answer. Limits: request line + headers ≤ 8 KiB (431), body ≤ 1 MiB (413), malformed request
// (400), idle keep-alive timeout 60 s, at most max_clients connections (one more is accepted and
// closed at once, with one warning). Threading: the io_context's single thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <set>

#include "web/api/router.hpp"

namespace mcemu::web::net {

struct HttpOptions {
  std::size_t max_clients = 32;
  std::size_t header_limit = 8 * 1024;
  std::size_t body_limit = 1024 * 1024;
  std::chrono::seconds idle_timeout{60};
};

// Must call `respond` exactly once, possibly later (on the loop thread).
using Handler = std::function<void(const api::Request&, api::Respond respond)>;

class HttpSession;

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
  void stop();
  std::size_t connection_count() const { return sessions_.size(); }

 private:
  friend class HttpSession;
  void do_accept();
  void forget(const std::shared_ptr<HttpSession>& s) { sessions_.erase(s); }

  boost::asio::ip::tcp::acceptor acceptor_;
  HttpOptions options_;
  Handler handler_;
  std::set<std::shared_ptr<HttpSession>> sessions_;
  bool accepting_ = false;
};

}  // namespace mcemu::web::net
