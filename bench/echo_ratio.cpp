// echo_ratio: how close mcemu's TCP path comes to the floor of a minimal server (issue 12).
//
// A minimal single-threaded Asio TCP echo server (a child process, like mcemu) and mcemu on
// loopback, driven by the same closed-loop client (bench/load_client.hpp): RefGo `TP\r` on 1 and
// 16 connections, an SDO upload of 6041h over SLCAN on 1 connection, and an SDO read of 6041h over
// the FAULHABER binary protocol (faulhaber.md §5: the 9-byte request, an 11-byte answer) against a
// second mcemu child running FH_MC5005; the echo server gets the same request bytes and sends them
// back. HTTP GET /api/v1/status on 1 and 8 keep-alive connections has its own anchor (issue 26): a
// minimal Boost.Beast server on one single-threaded Asio loop, as mcemu's, keep-alive, that answers
// every request with one constant response — the header fields and body of a real mcemu status
// answer fetched at start, so both send the same bytes and the ratio prices what mcemu does beyond
// parsing and writing HTTP. Rounds alternate mcemu / anchor several times; the medians of the rounds
// are printed with the ratios, and the CPU seconds each server used. Goal: mcemu ≥ 95 % of echo's
// throughput (≥ 90 % of the Beast anchor's for HTTP), p99 ≤ 1.25 × the anchor's p99.
//
// The CPU columns: all CPU (user + system) and the user part alone per request; at 16 connections
// both servers run at ~100 % of a core, so the throughput ratio follows the CPU-per-request ratio,
// and the user part is what mcemu's own code adds (the system part also grows with it: a slower
// server finds the client asleep more often, and each wake-up is paid inside sendto).
//
// Usage: echo_ratio [path/to/mcemu] [seconds per round, default 3] [rounds, default 5] [scenario filter]
// (the filter: only scenarios whose name contains it, e.g. "16 conn")
#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "bench/load_client.hpp"

namespace asio = boost::asio;
using tcp = asio::ip::tcp;
using namespace mcemu::bench;

namespace {

class EchoSession : public std::enable_shared_from_this<EchoSession> {
 public:
  explicit EchoSession(tcp::socket s) : socket_(std::move(s)) {}
  void start() { read(); }

 private:
  void read() {
    socket_.async_read_some(asio::buffer(buf_), [self = shared_from_this()](auto ec, std::size_t n) {
      if (ec) return;
      asio::async_write(self->socket_, asio::buffer(self->buf_.data(), n), [self](auto wec, std::size_t) {
        if (!wec) self->read();
      });
    });
  }
  tcp::socket socket_;
  std::array<char, 4096> buf_{};
};

void accept(tcp::acceptor& a) {
  a.async_accept([&a](auto ec, tcp::socket s) {
    if (!ec) {
      s.set_option(tcp::no_delay(true));
      std::make_shared<EchoSession>(std::move(s))->start();
    }
    accept(a);
  });
}

namespace beast = boost::beast;
namespace http = boost::beast::http;
using Response = http::response<http::string_body>;

// The HTTP anchor: one keep-alive connection of the minimal Beast server; every request gets a copy
// of the same response.
class BeastSession : public std::enable_shared_from_this<BeastSession> {
 public:
  BeastSession(tcp::socket s, const Response& r) : socket_(std::move(s)), response_(r) {}
  void start() { read(); }

 private:
  void read() {
    request_ = {};
    http::async_read(socket_, buffer_, request_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->response_.keep_alive(self->request_.keep_alive());
      http::async_write(self->socket_, self->response_, [self](beast::error_code wec, std::size_t) {
        if (!wec) self->read();
      });
    });
  }
  tcp::socket socket_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  Response response_;
};

void accept_http(tcp::acceptor& a, const Response& r) {
  a.async_accept([&a, &r](auto ec, tcp::socket s) {
    if (!ec) {
      s.set_option(tcp::no_delay(true));
      std::make_shared<BeastSession>(std::move(s), r)->start();
    }
    accept_http(a, r);
  });
}

// One GET of `target` from mcemu's HTTP port: the response the anchor will repeat.
Response fetch(std::uint16_t port, const std::string& target) {
  asio::io_context io;
  tcp::socket s(io);
  s.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, "127.0.0.1");
  http::write(s, req);
  beast::flat_buffer b;
  Response res;
  http::read(s, b, res);
  return res;
}

// Forks a single-threaded server child that runs `serve` on its acceptor; returns its port in
// c.ports[name].
template <typename Serve>
void start_server(Child& c, const std::string& name, Serve serve) {
  int p[2];
  if (::pipe(p) != 0) throw std::runtime_error("pipe");
  c.pid = ::fork();
  if (c.pid == 0) {
    asio::io_context io(1);
    tcp::acceptor a(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    const std::uint16_t port = a.local_endpoint().port();
    if (::write(p[1], &port, sizeof port) != sizeof port) std::_Exit(1);
    serve(a);
    io.run();
    std::_Exit(0);
  }
  std::uint16_t port = 0;
  if (::read(p[0], &port, sizeof port) != sizeof port) throw std::runtime_error(name + " server did not start");
  c.ports[name] = port;
  ::close(p[0]);
  ::close(p[1]);
}

// Forks the echo server; returns its port.
void start_echo(Child& c) {
  start_server(c, "echo", [](tcp::acceptor& a) { accept(a); });
}

struct Scenario {
  const char* name;
  const char* service;
  std::string request;
  Complete mcemu_complete;
  int connections;
  bool faulhaber = false;  // against the FH_MC5005 child instead of the MovingCap one
  bool http = false;       // anchored on the Beast server instead of echo
};

struct Round {
  double throughput, p50, p99, cpu_per_request_us, user_per_request_us;
};

Round measure(const Child& server, std::uint16_t port, const std::string& request, const Complete& complete,
              int connections, std::chrono::milliseconds duration) {
  const CpuTimes cpu0 = cpu_times(server.pid);
  const Stats st = closed_loop(port, request, complete, connections, duration);
  const CpuTimes cpu1 = cpu_times(server.pid);
  const auto per_request_us = [&](double seconds) {
    return st.requests ? seconds / static_cast<double>(st.requests) * 1e6 : 0;
  };
  return {st.throughput(), st.percentile(0.50), st.percentile(0.99), per_request_us(cpu1.total() - cpu0.total()),
          per_request_us(cpu1.user - cpu0.user)};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string binary = argc > 1 ? argv[1] : "build/server/mcemu";
  const auto seconds = std::chrono::milliseconds(argc > 2 ? std::atoi(argv[2]) * 1000 : 3000);
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
  const std::string filter = argc > 4 ? argv[4] : "";
  const auto state = std::filesystem::temp_directory_path() / ("mcemu-bench-" + std::to_string(::getpid()));

  Child echo;
  start_echo(echo);
  Child mcemu;
  start_mcemu(mcemu, binary, {"--max-clients", "32"}, state.string());

  const Complete refgo_reply = [](const std::string& b) { return !b.empty() && b.back() == '>'; };
  const Complete sdo_reply = [](const std::string& b) {
    const auto at = b.find("t5B2");
    return at != std::string::npos && b.back() == '\r' && b.size() > at + 4;
  };
  // An HTTP/1.1 response is complete when its body has Content-Length bytes.
  const Complete http_reply = [](const std::string& b) {
    const auto end = b.find("\r\n\r\n");
    if (end == std::string::npos) return false;
    const auto at = b.find("Content-Length: ");
    if (at == std::string::npos || at > end) return false;
    return b.size() >= end + 4 + std::stoul(b.substr(at + 16));
  };
  const std::string status_get = "GET /api/v1/status HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  // A FAULHABER frame is complete when it has L + 2 bytes (byte 1 is L).
  const Complete fh_frame = [](const std::string& b) {
    return b.size() >= 2 && b.size() >= static_cast<std::size_t>(static_cast<unsigned char>(b[1])) + 2;
  };
  const std::string fh_read_6041("\x53\x07\x01\x01\x41\x60\x00\x73\x45", 9);  // faulhaber.md §5
  const std::vector<Scenario> scenarios = {
      {"RefGo TP, 1 connection", "refgo", "TP\r", refgo_reply, 1},
      {"RefGo TP, 16 connections", "refgo", "TP\r", refgo_reply, 16},
      {"SDO upload 6041h, 1 connection", "slcan", "t63284041600000000000\r", sdo_reply, 1},
      // the status snapshot (web.md §8.2, ~1.3 KB of JSON) over keep-alive, against the Beast
      // anchor that sends the same response bytes
      {"HTTP GET /api/v1/status, 1 conn", "http", status_get, http_reply, 1, false, true},
      {"HTTP GET /api/v1/status, 8 conns", "http", status_get, http_reply, 8, false, true},
      {"SDO read 6041h, FAULHABER, 1 conn", "faulhaber", fh_read_6041, fh_frame, 1, true},
  };
  const auto selected = [&](const Scenario& s) { return std::string(s.name).find(filter) != std::string::npos; };
  // The HTTP anchor repeats one status answer of this mcemu (same header fields, same body size).
  Child anchor;
  Response status_response;
  if (std::any_of(scenarios.begin(), scenarios.end(), [&](const Scenario& s) { return s.http && selected(s); })) {
    status_response = fetch(mcemu.ports.at("http"), "/api/v1/status");
    start_server(anchor, "beast", [&status_response](tcp::acceptor& a) { accept_http(a, status_response); });
  }
  // The FAULHABER personality is its own process (a drive has one personality); started only when a
  // selected scenario needs it, with its own state directory.
  Child fh;
  if (std::any_of(scenarios.begin(), scenarios.end(), [&](const Scenario& s) { return s.faulhaber && selected(s); })) {
    start_mcemu(fh, binary, {"--model", "FH_MC5005", "--faulhaber-port", "0"}, state.string() + "-fh");
  }

  std::printf("echo_ratio: %d rounds of %.1f s per server and scenario, alternating; medians of the rounds\n", rounds,
              static_cast<double>(seconds.count()) / 1000.0);
  std::printf("load before: %s\n", load_line().c_str());
  std::printf("%-32s %-6s %12s %9s %9s %10s %10s\n", "scenario", "server", "requests/s", "p50 us", "p99 us",
              "cpu us/req", "user us/r");
  for (const auto& s : scenarios) {
    if (!selected(s)) continue;
    std::vector<double> mt, m50, m99, mc, mu, et, e50, e99, ec, eu;
    for (int r = 0; r < rounds; ++r) {
      const auto one = [&](bool use_mcemu) {
        const Child& drive = s.faulhaber ? fh : mcemu;
        const Child& base = s.http ? anchor : echo;
        const Child& server = use_mcemu ? drive : base;
        const std::uint16_t port = use_mcemu ? drive.ports.at(s.service) : base.ports.at(s.http ? "beast" : "echo");
        const std::size_t n = s.request.size();
        const Complete echo_reply = [n](const std::string& b) { return b.size() >= n; };
        const Complete& base_reply = s.http ? s.mcemu_complete : echo_reply;
        const Round x =
            measure(server, port, s.request, use_mcemu ? s.mcemu_complete : base_reply, s.connections, seconds);
        (use_mcemu ? mt : et).push_back(x.throughput);
        (use_mcemu ? m50 : e50).push_back(x.p50);
        (use_mcemu ? m99 : e99).push_back(x.p99);
        (use_mcemu ? mc : ec).push_back(x.cpu_per_request_us);
        (use_mcemu ? mu : eu).push_back(x.user_per_request_us);
      };
      // alternate which server goes first, so that a trend in the machine's load hits both
      one(r % 2 == 0);
      one(r % 2 != 0);
    }
    std::printf("%-32s %-6s %12.0f %9.1f %9.1f %10.2f %10.2f\n", s.name, "mcemu", median(mt), median(m50), median(m99),
                median(mc), median(mu));
    std::printf("%-32s %-6s %12.0f %9.1f %9.1f %10.2f %10.2f\n", "", s.http ? "beast" : "echo", median(et), median(e50),
                median(e99), median(ec), median(eu));
    std::printf("%-32s %-6s %11.1f%% %9s %8.2fx   (goal: >= %d %%, p99 <= 1.25x)\n", "", "ratio",
                100.0 * median(mt) / median(et), "", median(m99) / median(e99), s.http ? 90 : 95);
  }
  std::printf("load after: %s\n", load_line().c_str());
  std::filesystem::remove_all(state);
  std::filesystem::remove_all(state.string() + "-fh");
  return 0;
}
