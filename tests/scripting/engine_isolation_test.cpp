// Isolation of the script engine (scripting.md §10.1, §13.9) and the script's own sockets (§7,
// §13.6), with the real python3. No wall-clock speed is asserted (bench/ measures it); the loop's
// responsiveness is shown by handlers it keeps running while the script misbehaves.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

#include "tests/scripting/engine_fixture.hpp"

// GCC defines __SANITIZE_ADDRESS__ under -fsanitize=address, clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define MCEMU_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define MCEMU_TEST_ASAN 1
#endif
#endif
#ifdef MCEMU_TEST_ASAN
constexpr bool k_address_sanitizer = true;
#else
constexpr bool k_address_sanitizer = false;
#endif

namespace mcemu::scripting::test {
namespace {

// Counts handler runs of a 1 ms wall timer on the rig's loop while it lives.
struct Heartbeat {
  explicit Heartbeat(boost::asio::io_context& io) : timer(io) { arm(); }
  ~Heartbeat() { timer.cancel(); }
  void arm() {
    timer.expires_after(std::chrono::milliseconds(1));
    timer.async_wait([this](const boost::system::error_code& ec) {
      if (ec) return;
      ++beats;
      arm();
    });
  }
  boost::asio::steady_timer timer;
  int beats = 0;
};

void expect_loop_keeps_running(EngineRig& r) {
  Heartbeat h(r.io);
  ASSERT_TRUE(r.wait([&] { return h.beats >= 50; })) << "the loop stopped running other handlers";
}

TEST(EngineIsolation, SpinningScriptStopsAndTheLoopRuns) {
  EngineRig r;
  r.start("while True:\n    pass\n");
  r.advance(150);
  expect_loop_keeps_running(r);
  r.engine->stop();
  EXPECT_EQ(r.engine->state(), RunState::off);
  EXPECT_EQ(r.read(0x3500, 2), 0);
}

TEST(EngineIsolation, NoRequestReachesTheOdAfterStop) {
  EngineRig r;
  r.start("import mcdrive as mc\nn = 0\nwhile True:\n    n = (n + 1) % 1000\n    mc.WriteObject(0x340c, 1, n)\n");
  r.advance(150);
  ASSERT_TRUE(r.wait([&] { return r.get(0x340C, 1) > 10; }));
  expect_loop_keeps_running(r);
  r.engine->stop();
  const auto value = r.get(0x340C, 1);
  Heartbeat h(r.io);
  ASSERT_TRUE(r.wait([&] { return h.beats >= 100; }));
  EXPECT_EQ(r.get(0x340C, 1), value);
}

TEST(EngineIsolation, StopWhilePausedAndWhileBlocked) {
  EngineRig r;
  r.start("import time\ntime.sleep(100000)\n");
  r.advance(150);
  r.engine->stop();
  EXPECT_EQ(r.engine->state(), RunState::off);
  r.start("while True:\n    pass\n");
  r.advance(150);
  r.engine->pause();
  r.advance(5);
  r.engine->stop();
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineIsolation, DeepRecursionIsARuntimeError) {
  EngineRig r;
  ASSERT_TRUE(r.run("def f(n):\n    return f(n + 1)\nf(0)\n"));
  EXPECT_NE(r.text().find("RuntimeError: maximum recursion depth exceeded\r\n"), std::string::npos);
}

TEST(EngineIsolation, HugeAllocationIsAMemoryErrorAndMcemuDoesNotGrow) {
  EngineRig r;
  const auto before = rss_kib();
  ASSERT_TRUE(r.run("x = [0] * 10**9\n"));
  EXPECT_NE(r.text().find("  File \"<stdin>\", line 1, in <module>\r\nMemoryError: \r\n"), std::string::npos)
      << r.text();
  EXPECT_LT(rss_kib() - before, 5 * 1024);
}

TEST(EngineIsolation, EngineCrashWithStrictOff) {
  EngineSettings s;
  s.strict = false;
  EngineRig r("MC349", s);
  ASSERT_TRUE(r.run("import os\nprint('bye')\nos._exit(3)\n"));
  EXPECT_NE(r.text().find("bye\r\ncode: engine failure (exit status 3), script id: (empty)\n\r"), std::string::npos)
      << r.text();
}

TEST(EngineIsolation, EndlessPrintingIsBackpressured) {
  EngineRig r;
  std::size_t bytes = 0;
  r.start("while True:\n    print('x' * 1000)\n");
  r.advance(150);
  const auto before = rss_kib();
  expect_loop_keeps_running(r);
  for (const auto& m : r.console) bytes += m.size();
  EXPECT_GT(bytes, 10000U);
  r.console.clear();  // the rig keeps every message; mcemu's UDP console bounds its own queue
  expect_loop_keeps_running(r);
  r.engine->stop();
  EXPECT_EQ(r.engine->state(), RunState::off);
  r.console.clear();
  r.console.shrink_to_fit();
  if (!k_address_sanitizer) {  // ASan keeps freed memory in its quarantine
    EXPECT_LT(rss_kib() - before, 5 * 1024);
  }
}

// ---- mcnet (scripting.md §7)

std::uint16_t free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t n = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
  close(fd);
  return ntohs(a.sin_port);
}

int connect_to(std::uint16_t port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  return fd;
}

std::string recv_some(int fd) {
  char buf[512];
  const ssize_t n = recv(fd, buf, sizeof buf, MSG_DONTWAIT);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
}

TEST(EngineMcnet, TcpEchoServerReopensAfterRestart) {
  EngineRig r;
  const std::uint16_t port = free_port();
  const std::string script = "import mcnet\nimport time\ns = mcnet.McNet('SERVER:" + std::to_string(port) +
                             "')\ns.set_line_mode(1, 0, 10, 0, 0, 1000)\nprint('listening')\n"
                             "while True:\n    l = s.readline()\n    if l:\n        s.write('echo ' + l)\n";
  for (int round = 0; round < 2; ++round) {  // the restarted script binds its port again (TIME_WAIT)
    r.start(script);
    ASSERT_TRUE(r.advance_until([&] { return r.text().find("listening") != std::string::npos; }, 5000)) << r.text();
    const int fd = connect_to(port);
    std::string got;
    bool sent = false;
    ASSERT_TRUE(r.advance_until(
        [&] {
          if (!sent) sent = send(fd, "hi\n", 3, MSG_NOSIGNAL) == 3;
          got += recv_some(fd);
          return got == "echo hi\n";
        },
        20000))
        << got;
    r.engine->stop();
    // the kernel closed the script's sockets with its process
    ASSERT_TRUE(r.wait([&] {
      char c;
      return recv(fd, &c, 1, MSG_DONTWAIT) == 0;
    }));
    close(fd);
  }
}

TEST(EngineMcnet, TcpClientConnectsAndUdpPeer) {
  EngineRig r;
  const int lst = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(lst, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  listen(lst, 1);
  socklen_t n = sizeof a;
  getsockname(lst, reinterpret_cast<sockaddr*>(&a), &n);
  const int udp = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  // The peer form binds the same port number locally (on the drive's 127.0.0.1): the test's peer
  // listens on another loopback address.
  sockaddr_in u{};
  u.sin_family = AF_INET;
  u.sin_addr.s_addr = htonl(0x7F000002);
  const std::uint16_t uport = free_port();
  u.sin_port = htons(uport);
  ASSERT_EQ(bind(udp, reinterpret_cast<sockaddr*>(&u), sizeof u), 0);
  r.start("import mcnet\nimport time\nc = mcnet.McNet('127.0.0.1:" + std::to_string(ntohs(a.sin_port)) +
          "')\nprint(c.is_open())\nwhile not c.is_connected():\n    time.sleep_ms(1)\nprint(c.write(b'hello'))\n"
          "p = mcnet.McNet('UDP:127.0.0.2:" +
          std::to_string(uport) +
          "')\n"
          "print(p.write('dgram'), c.in_waiting())\n"
          "c.close()\nprint(c.is_open(), c.write('x'), c.read(), c.in_waiting())\n");
  ASSERT_TRUE(r.advance_until([&] { return r.engine->state() == RunState::off; }, 20000)) << r.text();
  EXPECT_NE(r.text().find("True\r\n5\r\n5 0\r\nFalse -1 None -1\r\n"), std::string::npos) << r.text();
  const int conn = accept(lst, nullptr, nullptr);
  ASSERT_GE(conn, 0);
  EXPECT_EQ(recv_some(conn), "hello");
  char buf[64];
  EXPECT_EQ(recv(udp, buf, sizeof buf, MSG_DONTWAIT), 5);
  close(conn);
  close(lst);
  close(udp);
}

TEST(EngineMcnet, NinthObjectAndBadSettingsRaiseOSError) {
  EngineRig r;
  const std::uint16_t base = free_port();
  std::string s = "import mcnet\nobjs = []\nfor i in range(8):\n    objs.append(mcnet.McNet('UDP:%d' % (" +
                  std::to_string(base) + " + i)))\n";
  s += "try:\n    mcnet.McNet('UDP:" + std::to_string(base) + "')\nexcept OSError as e:\n    print(e.args[0])\n";
  s += "objs[0].close()\ntry:\n    mcnet.McNet('SERVER:x')\nexcept OSError as e:\n    print(e.args[0])\n";
  s += "try:\n    mcnet.McNet('SERVER:" + std::to_string(base + 1) +
       "')\n    print('tcp ok')\nexcept OSError as e:\n"
       "    print(e)\n";
  ASSERT_TRUE(r.run(s));
  EXPECT_NE(r.text().find("23\r\n22\r\n"), std::string::npos) << r.text();
}

}  // namespace
}  // namespace mcemu::scripting::test
