// The shared TCP adapter with a real socket on 127.0.0.1 (refgo.md §1, slcan-canopen.md §3.1).
// The server runs its io_context on a second thread; the test talks through blocking sockets.
#include "protocols/line/net/line_server.hpp"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <future>
#include <thread>

#include "protocols/line/line_assembler.hpp"

namespace mcemu::line::net {
namespace {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

// Answers every line with "<line>\r\n" repeated `repeat` times; counts received bytes.
class EchoSession final : public StreamSession {
 public:
  EchoSession(std::atomic<std::size_t>& received, std::size_t repeat, std::function<void(EchoSession*)> on_create)
      : received_(received), repeat_(repeat) {
    if (on_create) on_create(this);
  }
  void receive(std::string_view bytes) override {
    received_ += bytes.size();
    for (auto& l : assembler_.feed(bytes)) {
      for (std::size_t i = 0; i < repeat_; ++i) out_ += l.text + "\r\n";
    }
  }
  std::string take_output() override { return std::exchange(out_, {}); }
  void peer_closed() override { closed_ = true; }
  bool finished() const override { return closed_; }
  void closing(std::string_view reason) override {
    if (on_closing) on_closing(reason);
  }
  std::function<void(std::string_view)> on_closing;
  void push(const std::string& s) {
    out_ += s;
    wake();
  }

 private:
  std::atomic<std::size_t>& received_;
  std::size_t repeat_;
  LineAssembler assembler_{255, keep_all};
  std::string out_;
  bool closed_ = false;
};

struct Server {
  explicit Server(LineServerOptions o, std::size_t repeat = 1) {
    server = std::make_unique<LineServer>(
        io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0), std::move(o), [this, repeat](const PeerInfo&) {
          auto s = std::make_unique<EchoSession>(received, repeat, [this](EchoSession* e) { last = e; });
          s->on_closing = [this](std::string_view reason) { overflow_reported = reason == "queue overflow"; };
          return s;
        });
    server->start();
    thread = std::thread([this] { io.run(); });
  }
  ~Server() {
    asio::post(io, [this] { server->stop(); });
    work.reset();
    io.stop();
    thread.join();
  }
  tcp::socket connect() {
    tcp::socket s(client_io);
    s.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), server->port()));
    return s;
  }
  std::string read_all(tcp::socket& s) {
    std::string out;
    boost::system::error_code ec;
    std::array<char, 65536> buf{};
    for (;;) {
      const auto n = s.read_some(asio::buffer(buf), ec);
      if (ec) break;
      out.append(buf.data(), n);
    }
    return out;
  }

  asio::io_context io;
  asio::io_context client_io;
  std::unique_ptr<asio::executor_work_guard<asio::io_context::executor_type>> work =
      std::make_unique<asio::executor_work_guard<asio::io_context::executor_type>>(io.get_executor());
  std::unique_ptr<LineServer> server;
  std::atomic<std::size_t> received{0};
  std::atomic<EchoSession*> last{nullptr};
  std::atomic<bool> overflow_reported{false};
  std::thread thread;
};

LineServerOptions options(std::size_t max_clients = 8) {
  LineServerOptions o;
  o.name = "test";
  o.max_clients = max_clients;
  return o;
}

TEST(LineServer, AnswersCompleteLinesAfterFinThenCloses) {
  Server srv(options());
  auto s = srv.connect();
  asio::write(s, asio::buffer(std::string("A\rB\r\nC")));
  s.shutdown(tcp::socket::shutdown_send);
  EXPECT_EQ(srv.read_all(s), "A\r\nB\r\n") << "the unterminated C is discarded";
}

TEST(LineServer, PipelinedLinesInOrderSplitAnyhow) {
  Server srv(options());
  auto s = srv.connect();
  std::string expected;
  for (int i = 0; i < 200; ++i) {
    std::string line = "L";
    line += std::to_string(i);
    expected += line + "\r\n";
    const std::string wire = line + "\r";
    for (char c : wire) asio::write(s, asio::buffer(&c, 1));
  }
  s.shutdown(tcp::socket::shutdown_send);
  EXPECT_EQ(srv.read_all(s), expected);
}

TEST(LineServer, LimitClosesTheExtraConnectionWithoutAByte) {
  Server srv(options(2));
  auto a = srv.connect();
  auto b = srv.connect();
  asio::write(a, asio::buffer(std::string("x\r")));  // both accepted and served
  std::array<char, 3> buf{};
  asio::read(a, asio::buffer(buf));
  auto c = srv.connect();
  boost::system::error_code ec;
  const auto n = c.read_some(asio::buffer(buf), ec);
  EXPECT_EQ(n, 0u);
  EXPECT_TRUE(ec == asio::error::eof || ec == asio::error::connection_reset) << ec.message();
  // the two others still work
  asio::write(b, asio::buffer(std::string("y\r")));
  asio::read(b, asio::buffer(buf));
  EXPECT_EQ(std::string(buf.data(), 3), "y\r\n");
}

TEST(LineServer, AsynchronousOutputIsWrittenOnWake) {
  Server srv(options());
  auto s = srv.connect();
  asio::write(s, asio::buffer(std::string("hi\r")));
  std::array<char, 4> buf{};
  asio::read(s, asio::buffer(buf));
  ASSERT_NE(srv.last.load(), nullptr);
  asio::post(srv.io, [&] { srv.last.load()->push("late\r"); });
  std::array<char, 5> late{};
  asio::read(s, asio::buffer(late));
  EXPECT_EQ(std::string(late.data(), 5), "late\r");
}

TEST(LineServer, SlowReaderPausesReadingAndLosesNothing) {
  auto o = options();
  o.pause_above = 64 * 1024;
  o.resume_below = 16 * 1024;
  Server srv(o, 100);  // each 10-byte line produces 1.1 KiB of output
  auto s = srv.connect();
  const std::string line = "123456789\r";
  std::string all;
  for (int i = 0; i < 40000; ++i) all += line;
  // send without reading; the server must stop reading long before it has everything
  auto sender = std::async(std::launch::async, [&] { asio::write(s, asio::buffer(all)); });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  std::size_t last = 0;
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const std::size_t now = srv.received;
    if (now == last || std::chrono::steady_clock::now() > deadline) break;
    last = now;
  }
  EXPECT_LT(srv.received.load(), all.size()) << "reading stopped while the client does not read";
  // now read everything: every reply arrives, in order
  std::string got;
  std::array<char, 65536> buf{};
  const std::size_t expected_size = 40000u * 100u * 11u;
  while (got.size() < expected_size) {
    got.append(buf.data(), s.read_some(asio::buffer(buf)));
  }
  sender.get();
  EXPECT_EQ(got.size(), expected_size);
  EXPECT_EQ(got.substr(0, 11), "123456789\r\n");
}

TEST(LineServer, CloseOnOverflowDropsAClientThatNeverReads) {
  auto o = options();
  o.pause_above = 32 * 1024;
  o.close_on_overflow = true;
  Server srv(o, 1000);  // 11 KB of output per line
  auto s = srv.connect();
  boost::system::error_code ec;
  for (int i = 0; i < 2000 && !ec; ++i) asio::write(s, asio::buffer(std::string("123456789\r")), ec);
  // the server closes the connection: reading ends with EOF or reset, not a hang
  std::array<char, 65536> buf{};
  std::size_t total = 0;
  for (;;) {
    const auto n = s.read_some(asio::buffer(buf), ec);
    if (ec) break;
    total += n;
  }
  EXPECT_TRUE(ec == asio::error::eof || ec == asio::error::connection_reset) << ec.message();
  EXPECT_LT(total, 2000u * 11000u);
  EXPECT_TRUE(srv.overflow_reported) << "the session is told why (slcan-canopen.md §11.2 trace)";
}

TEST(LineServer, SocketOptionsOfRefgoSection13) {
  asio::io_context io;
  tcp::acceptor acc(io, tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
  tcp::socket client(io);
  client.connect(acc.local_endpoint());
  tcp::socket accepted = acc.accept();
  apply_stream_socket_options(accepted);
  const int fd = accepted.native_handle();
  const auto get = [fd](int level, int opt) {
    int v = 0;
    socklen_t len = sizeof v;
    EXPECT_EQ(::getsockopt(fd, level, opt, &v, &len), 0);
    return v;
  };
  EXPECT_NE(get(IPPROTO_TCP, TCP_NODELAY), 0);
  EXPECT_NE(get(SOL_SOCKET, SO_KEEPALIVE), 0);
  EXPECT_EQ(get(IPPROTO_TCP, TCP_KEEPIDLE), 10);
  EXPECT_EQ(get(IPPROTO_TCP, TCP_KEEPINTVL), 5);
  EXPECT_EQ(get(IPPROTO_TCP, TCP_KEEPCNT), 3);
  EXPECT_EQ(get(IPPROTO_TCP, TCP_USER_TIMEOUT), 25000);
}

}  // namespace
}  // namespace mcemu::line::net
