// A drive unit's shutdown (issue 23): the unit with its real listeners (RefGo, SLCAN, the HTTP server
// with its WebSocket hub) on 127.0.0.1, clients in the middle of their work — a WebSocket
// subscribed to status, scope and trace, a RefGo and an SLCAN session, a Store whose file is still
// being written, requests not yet read — then shutdown(), the unit destroyed, and the loop run
// until every handler left in it has run. Nothing may touch the destroyed bundle (its trace ring,
// dictionary, persistence service): the sanitizer build (tools/dev test) turns any such touch into
// a failure; every build checks that each client is disconnected and nothing hangs.
#include "server/drive_unit.hpp"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "web/net/http_server.hpp"

namespace mcemu::server {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// A blocking TCP client; every read is bounded by poll().
class Client {
 public:
  explicit Client(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~Client() { ::close(fd_); }
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  bool connected() const { return connected_; }
  void send(std::string_view bytes) { (void)::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }
  // What arrived so far, without waiting; sets closed() at EOF or reset.
  const std::string& received() {
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) break;
      char buf[65536];
      const auto n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) {
        closed_ = true;
        break;
      }
      in_.append(buf, static_cast<std::size_t>(n));
    }
    return in_;
  }
  bool closed() {
    received();
    return closed_;
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
  bool closed_ = false;
  std::string in_;
};

// Runs the loop until `done` holds (at most `limit`); true if it did.
bool pump_until(boost::asio::io_context& io, const std::function<bool()>& done, std::chrono::milliseconds limit = 5s) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    io.restart();
    io.run_for(1ms);
  }
  return done();
}

// One masked WebSocket text frame (RFC 6455 §5.3: a client masks what it sends).
std::string ws_text(const std::string& payload) {
  std::string f;
  f += static_cast<char>(0x81);
  f += static_cast<char>(0x80 | payload.size());  // < 126 bytes here
  const char mask[4] = {1, 2, 3, 4};
  f.append(mask, 4);
  for (std::size_t i = 0; i < payload.size(); ++i) f += static_cast<char>(payload[i] ^ mask[i % 4]);
  return f;
}

bool store_being_written(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    if (e.path().extension() == ".tmp") return true;
  }
  return false;
}

TEST(DriveUnitShutdown, NothingTouchesTheBundleOnceItIsGone) {
  const fs::path dir = fs::path(::testing::TempDir()) / "drive_unit_shutdown";
  fs::remove_all(dir);
  Settings s;
  s.refgo_port = s.slcan_port = s.http_port = s.udp_port = 0;
  s.state_dir = dir.string();
  // Each chunk of the state file takes 10 ms, so the Store below is still being written at shutdown
  // and its completion reaches the loop after the unit is gone.
  ::setenv("MCEMU_TEST_STORE_DELAY_US", "10000", 1);
  boost::asio::io_context io;
  auto unit = std::make_unique<DriveUnit>(io, s, 1, "");
  ::unsetenv("MCEMU_TEST_STORE_DELAY_US");
  unit->start();
  const auto ports = unit->ports();
  ASSERT_NE(ports.http, 0);

  // a WebSocket with every topic: status, scope and trace messages flow every 50 ms
  Client ws(ports.http);
  ws.send(
      "GET /api/v1/ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  ASSERT_TRUE(pump_until(io, [&] { return ws.received().find("\r\n\r\n") != std::string::npos; }));
  ASSERT_EQ(ws.received().rfind("HTTP/1.1 101", 0), 0u) << ws.received();
  ws.send(ws_text(R"({"subscribe":["status","scope","trace"]})"));
  ASSERT_TRUE(pump_until(io, [&] { return ws.received().find("\"type\":\"status\"") != std::string::npos; }));

  Client refgo(ports.refgo);
  refgo.send("TP\r");
  ASSERT_TRUE(pump_until(io, [&] { return refgo.received().find('>') != std::string::npos; }));
  Client slcan(ports.slcan);
  slcan.send("t63284041600000000000\r");
  ASSERT_TRUE(pump_until(io, [&] { return slcan.received().find("t5B2") != std::string::npos; }));

  // a Store whose file is being written: its answer is pending
  Client store(ports.http);
  store.send("POST /api/v1/store HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 0\r\n\r\n");
  ASSERT_TRUE(pump_until(io, [&] { return store_being_written(dir); })) << "the Store is being written";

  // requests that arrive as the unit shuts down (not read yet)
  Client late(ports.http);
  late.send("GET /api/v1/status HTTP/1.1\r\nHost: x\r\n\r\n");
  refgo.send("TP\rOR6041,0\r");
  slcan.send("t63284041600000000000\r");

  unit->shutdown();
  unit.reset();
  // every handler still queued runs now: accept and read completions, WebSocket timers, the Store's
  // completion from the persistence worker
  io.restart();
  io.run_for(2s);
  EXPECT_TRUE(io.stopped()) << "nothing is left waiting in the loop";

  for (auto* c : {&ws, &refgo, &slcan, &store}) EXPECT_TRUE(c->closed()) << "disconnected at shutdown";
  EXPECT_EQ(store.received().find("HTTP/1.1 200"), std::string::npos) << "the Store is not answered 200 "
                                                                         "by a drive that is gone";
  const auto& answer = late.received();
  EXPECT_TRUE(late.closed() || answer.rfind("HTTP/1.1 503", 0) == 0) << answer;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mcemu::server
