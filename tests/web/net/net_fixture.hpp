// Shared pieces of the in-process tests of web/net: an HttpServer running its io_context on a second
// thread, a raw blocking TCP client (POSIX sockets with poll deadlines, so a broken server fails a
// test instead of hanging it) and a Beast WebSocket client whose operations run with a deadline.
#pragma once

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <csignal>
#include <cstring>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "web/net/http_server.hpp"

namespace mcemu::web::net::test {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using namespace std::chrono_literals;

inline bool poll_until(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 5s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(2ms);
  }
  return condition();
}

// The server under test on 127.0.0.1, port 0, with its loop on a thread of its own.
class TestServer {
 public:
  TestServer(HttpOptions options, Handler handler, HttpObserver observer = {}) {
    std::signal(SIGPIPE, SIG_IGN);
    server_ = std::make_unique<HttpServer>(io_, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0), options,
                                           std::move(handler));
    server_->set_observer(std::move(observer));
    server_->start();
    port_ = server_->port();
    thread_ = std::thread([this] { io_.run(); });
  }
  ~TestServer() {
    on_loop([this] {
      server_->stop();
      return 0;
    });
    work_.reset();
    thread_.join();
    server_.reset();
  }
  TestServer(const TestServer&) = delete;
  TestServer& operator=(const TestServer&) = delete;

  std::uint16_t port() const { return port_; }
  HttpServer& server() { return *server_; }
  asio::io_context& io() { return io_; }

  // Runs f on the server's loop and returns its result.
  template <class F>
  auto on_loop(F f) -> decltype(f()) {
    std::packaged_task<decltype(f())()> task(std::move(f));
    auto result = task.get_future();
    asio::post(io_, [&task] { task(); });
    return result.get();
  }
  std::size_t connections() {
    return on_loop([this] { return server_->connection_count(); });
  }

 private:
  asio::io_context io_;
  asio::executor_work_guard<asio::io_context::executor_type> work_ = asio::make_work_guard(io_);
  std::unique_ptr<HttpServer> server_;
  std::uint16_t port_ = 0;
  std::thread thread_;
};

struct RawResponse {
  int status = 0;
  std::map<std::string, std::string> headers;  // names lower-cased
  std::string body;
  std::string head;  // status line + headers as received
  bool has(const std::string& name) const { return headers.count(name) > 0; }
  std::string get(const std::string& name) const {
    const auto it = headers.find(name);
    return it == headers.end() ? std::string{} : it->second;
  }
};

// A blocking TCP client with deadlines on every read.
class RawClient {
 public:
  explicit RawClient(std::uint16_t port, int rcvbuf = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (rcvbuf > 0) ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~RawClient() { close(); }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return connected_; }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  void shutdown_send() { ::shutdown(fd_, SHUT_WR); }

  // false when the peer closed or reset.
  bool send(std::string_view bytes) {
    while (!bytes.empty()) {
      const auto n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
  }

  // Some bytes, "" at EOF or reset, nullopt when nothing arrived within `timeout`.
  std::optional<std::string> read_some(std::chrono::milliseconds timeout = 5s) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
    char buf[65536];
    const auto n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) {
      eof_ = true;
      return std::string{};
    }
    return std::string(buf, static_cast<std::size_t>(n));
  }

  // true when the server closed the connection (EOF or reset) within `timeout`; bytes that arrive
  // first are appended to `pending_`.
  bool wait_closed(std::chrono::milliseconds timeout = 5s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!eof_) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      auto s = read_some(left);
      if (!s) return false;
      pending_ += *s;
    }
    return true;
  }

  // One response (Content-Length framed, or none for 1xx/204/304/HEAD); nullopt on timeout/EOF.
  std::optional<RawResponse> read_response(bool head = false, std::chrono::milliseconds timeout = 5s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    auto fill = [&](std::size_t want) {
      while (pending_.size() < want || want == 0) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0) return false;
        auto s = read_some(left);
        if (!s || s->empty()) return false;
        pending_ += *s;
        if (want == 0) return true;
      }
      return true;
    };
    std::size_t end;
    while ((end = pending_.find("\r\n\r\n")) == std::string::npos) {
      if (!fill(0)) return std::nullopt;
    }
    RawResponse r;
    r.head = pending_.substr(0, end + 4);
    pending_.erase(0, end + 4);
    std::size_t line_end = r.head.find("\r\n");
    const std::string status_line = r.head.substr(0, line_end);
    if (status_line.size() < 12) return std::nullopt;
    r.status = std::stoi(status_line.substr(9, 3));
    std::size_t pos = line_end + 2;
    while (pos < r.head.size() - 2) {
      const auto e = r.head.find("\r\n", pos);
      const std::string line = r.head.substr(pos, e - pos);
      const auto colon = line.find(':');
      std::string name = line.substr(0, colon);
      for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      std::string value = line.substr(colon + 1);
      while (!value.empty() && value.front() == ' ') value.erase(0, 1);
      r.headers[name] = value;
      pos = e + 2;
    }
    const bool no_body = head || (r.status >= 100 && r.status < 200) || r.status == 204 || r.status == 304;
    if (!no_body && r.has("content-length")) {
      const auto n = static_cast<std::size_t>(std::stoull(r.get("content-length")));
      if (!fill(n)) return std::nullopt;
      r.body = pending_.substr(0, n);
      pending_.erase(0, n);
    }
    return r;
  }

  const std::string& pending() const { return pending_; }

 private:
  int fd_ = -1;
  bool connected_ = false;
  bool eof_ = false;
  std::string pending_;
};

inline std::string get_request(const std::string& target, const std::string& extra = {}) {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + extra + "\r\n";
}

// A Beast WebSocket client with its own io_context, run only while an operation is pending — so,
// like a real client, it answers pings only while it reads.
class TestWs {
 public:
  explicit TestWs(std::uint16_t port) : port_(port), ws_(io_) {
    ws_.control_callback([this](websocket::frame_type kind, beast::string_view) {
      if (kind == websocket::frame_type::ping) ++pings_;
    });
  }

  // The handshake's HTTP answer (101 on success); `headers` are added to the upgrade request.
  int handshake(const std::vector<std::pair<std::string, std::string>>& headers = {},
                std::chrono::milliseconds timeout = 5s) {
    beast::error_code ec;
    beast::get_lowest_layer(ws_).connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port_), ec);
    if (ec) return -1;
    ws_.set_option(websocket::stream_base::decorator([headers](websocket::request_type& req) {
      for (const auto& [k, v] : headers) req.set(k, v);
    }));
    websocket::response_type& res = response_;
    bool done = false;
    ws_.async_handshake(res, "127.0.0.1:" + std::to_string(port_), "/api/v1/ws", [&](beast::error_code e) {
      ec = e;
      done = true;
    });
    run(done, timeout);
    return done ? static_cast<int>(res.result_int()) : -1;
  }

  // The next message; nullopt when the connection ended (see error(), reason()) or on timeout.
  std::optional<std::string> read(std::chrono::milliseconds timeout = 5s) {
    beast::flat_buffer buffer;
    bool done = false;
    ws_.async_read(buffer, [&](beast::error_code e, std::size_t) {
      error_ = e;
      done = true;
    });
    run(done, timeout);
    if (!done) {
      timed_out_ = true;
      return std::nullopt;
    }
    if (error_) return std::nullopt;
    return beast::buffers_to_string(buffer.data());
  }

  // Reads until a message satisfies `pred`; nullopt when the connection ends or time runs out.
  std::optional<std::string> read_until(const std::function<bool(const std::string&)>& pred,
                                        std::chrono::milliseconds timeout = 5s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      auto m = read(left);
      if (!m) return std::nullopt;
      if (pred(*m)) return m;
    }
  }

  bool write(const std::string& text, std::chrono::milliseconds timeout = 5s) {
    bool done = false;
    beast::error_code ec;
    ws_.text(true);
    ws_.async_write(asio::buffer(text), [&](beast::error_code e, std::size_t) {
      ec = e;
      done = true;
    });
    run(done, timeout);
    return done && !ec;
  }

  beast::error_code error() const { return error_; }
  const websocket::response_type& response() const { return response_; }
  bool timed_out() const { return timed_out_; }
  websocket::close_reason reason() const { return ws_.reason(); }
  int pings() const { return pings_; }
  websocket::stream<beast::tcp_stream>& stream() { return ws_; }

 private:
  void run(bool& done, std::chrono::milliseconds timeout) {
    io_.restart();
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done && std::chrono::steady_clock::now() < deadline)
      io_.run_one_for(deadline - std::chrono::steady_clock::now());
    if (!done) {
      beast::get_lowest_layer(ws_).socket().cancel();
      io_.restart();
      io_.run_for(1s);
    }
  }

  std::uint16_t port_;
  asio::io_context io_;
  websocket::stream<beast::tcp_stream> ws_;
  websocket::response_type response_;
  beast::error_code error_;
  bool timed_out_ = false;
  int pings_ = 0;
};

}  // namespace mcemu::web::net::test
