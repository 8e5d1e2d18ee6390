// HttpServer with a real socket on 127.0.0.1 (web.md §1.1, §1.2, §1.4): keep-alive, limits,
// error statuses readable by a client still sending, 100-continue, HEAD, timeouts, the connection
// limit, and clients that are slow to send or never read.
#include <gtest/gtest.h>

#include <thread>

#include "protocols/line/net/line_server.hpp"
#include "tests/web/net/net_fixture.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::net::test {
namespace {

// The handler of these tests: a few paths with known answers.
void handle(const api::Request& r, const api::Respond& respond, asio::io_context& io) {
  const std::string path = r.target.substr(0, r.target.find('?'));
  api::Response out;
  out.content_type = "text/plain";
  if (path == "/echo") {
    out.body = r.method + " " + r.target + " " + r.body;
  } else if (path == "/len") {
    out.body = std::to_string(r.body.size());
  } else if (path == "/big") {
    out.body.assign(32 * 1024 * 1024, 'x');
  } else if (path == "/close") {
    out.body = "bye";
    out.close = true;
  } else if (path == "/later") {
    asio::post(io, [respond] {
      api::Response late;
      late.body = "late";
      respond(late);
    });
    return;
  } else if (path == "/twice") {
    out.body = "first";
    respond(out);
    out.body = "second";
  } else if (path == "/throw") {
    throw std::runtime_error("handler failed");
  } else if (path == "/header") {
    const auto v = r.header("x-test");
    out.body = v ? std::string(*v) : "-";
  } else if (path == "/fields") {  // extra fields in order; the second tries to end the header early
    out.headers.emplace_back("Cache-Control", "no-store");
    out.headers.emplace_back("X-Echo", "a\r\n\r\nInjected: yes");
    out.body = "ok";
  } else {
    out.status = 404;
    out.body = "no";
  }
  respond(out);
}

struct Recorder {
  std::vector<std::uint64_t> opened;
  std::vector<std::uint64_t> closed;
  std::vector<HttpObserver::Answer> answers;  // peer/method/target copied below
  std::vector<std::string> methods;
  std::vector<std::string> targets;
};

class HttpServerTest : public ::testing::Test {
 protected:
  void start(HttpOptions o = {}) {
    HttpObserver obs;
    obs.opened = [this](std::uint64_t c, std::string_view) { rec_.opened.push_back(c); };
    obs.closed = [this](std::uint64_t c) { rec_.closed.push_back(c); };
    obs.answered = [this](const HttpObserver::Answer& a) {
      rec_.answers.push_back({a.conn, {}, {}, {}, a.status, a.polling});
      rec_.methods.emplace_back(a.method);
      rec_.targets.emplace_back(a.target);
    };
    server_ = std::make_unique<TestServer>(
        o, [this](const api::Request& r, api::Respond respond) { handle(r, respond, server_->io()); }, obs);
  }
  Recorder recorded() {
    return server_->on_loop([this] { return rec_; });
  }
  std::uint16_t port() const { return server_->port(); }

  Recorder rec_;  // touched on the loop thread only; declared first so that it outlives the server
  std::unique_ptr<TestServer> server_;
};

TEST_F(HttpServerTest, KeepAliveReusesOneConnection) {
  start();
  RawClient c(port());
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(c.send(get_request("/echo?i=" + std::to_string(i))));
    const auto r = c.read_response();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body, "GET /echo?i=" + std::to_string(i) + " ");
    EXPECT_NE(r->get("connection"), "close");
    EXPECT_EQ(r->get("server"), "mcemu");
  }
  EXPECT_EQ(server_->connections(), 1U);
  const auto rec = recorded();
  ASSERT_EQ(rec.opened.size(), 1U);
  ASSERT_EQ(rec.answers.size(), 3U);
  for (const auto& a : rec.answers) {
    EXPECT_EQ(a.conn, rec.opened[0]);
    EXPECT_EQ(a.status, 200);
  }
  EXPECT_EQ(rec.methods[2], "GET");
  EXPECT_EQ(rec.targets[2], "/echo?i=2");
}

// A line session that answers nothing.
class SilentSession final : public line::StreamSession {
 public:
  void receive(std::string_view) override {}
  std::string take_output() override { return {}; }
  void peer_closed() override { closed_ = true; }
  bool finished() const override { return closed_; }

 private:
  bool closed_ = false;
};

// base/connection_ids.hpp: a drive's listeners share one counter, so the trace's `conn` names one
// connection whatever its channel. Here an HTTP server and a line server take turns.
TEST_F(HttpServerTest, ConnectionIdsSharedWithALineServer) {
  HttpOptions o;
  o.ids = std::make_shared<base::ConnectionIds>();
  start(o);
  std::vector<std::uint64_t> line_ids;  // touched on the loop thread only
  auto line = server_->on_loop([&] {
    line::net::LineServerOptions lo;
    lo.name = "test";
    lo.ids = o.ids;
    auto s = std::make_unique<line::net::LineServer>(
        server_->io(), tcp::endpoint(asio::ip::make_address("127.0.0.1"), 0), lo,
        [&line_ids](const line::net::PeerInfo& p) -> std::unique_ptr<line::StreamSession> {
          line_ids.push_back(p.id);
          return std::make_unique<SilentSession>();
        });
    s->start();
    return s;
  });
  const auto line_port = server_->on_loop([&] { return line->port(); });
  const auto line_connected = [&](std::size_t n) {
    return poll_until([&] { return server_->on_loop([&] { return line_ids.size(); }) == n; });
  };
  RawClient h1(port());
  ASSERT_TRUE(h1.send(get_request("/echo")));
  ASSERT_TRUE(h1.read_response());
  RawClient l1(line_port);
  ASSERT_TRUE(line_connected(1));
  RawClient h2(port());
  ASSERT_TRUE(h2.send(get_request("/echo")));
  ASSERT_TRUE(h2.read_response());
  RawClient l2(line_port);
  ASSERT_TRUE(line_connected(2));
  const auto rec = recorded();
  EXPECT_EQ(rec.opened, (std::vector<std::uint64_t>{1, 3}));
  EXPECT_EQ(server_->on_loop([&] { return line_ids; }), (std::vector<std::uint64_t>{2, 4}));
  server_->on_loop([&] {
    line->stop();
    line.reset();
    return 0;
  });
}

// Without a shared counter each server counts from 1 on its own.
TEST_F(HttpServerTest, ConnectionIdsOfItsOwnWithoutASharedCounter) {
  start();
  RawClient a(port());
  ASSERT_TRUE(a.send(get_request("/echo")));
  ASSERT_TRUE(a.read_response());
  RawClient b(port());
  ASSERT_TRUE(b.send(get_request("/echo")));
  ASSERT_TRUE(b.read_response());
  EXPECT_EQ(recorded().opened, (std::vector<std::uint64_t>{1, 2}));
}

// web.md §8.6: a request with the header X-Mcemu-Poll (the pages' timers) is reported as polling.
TEST_F(HttpServerTest, ThePollHeaderIsReported) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send("GET /echo HTTP/1.1\r\nHost: x\r\nX-Mcemu-Poll: 1\r\n\r\n"));
  ASSERT_TRUE(c.read_response());
  ASSERT_TRUE(c.send(get_request("/echo")));  // the same connection, no header
  ASSERT_TRUE(c.read_response());
  ASSERT_TRUE(c.send("GET /nothing HTTP/1.1\r\nHost: x\r\nx-mcemu-poll: \r\n\r\n"));  // any case, any value
  ASSERT_TRUE(c.read_response());
  const auto rec = recorded();
  ASSERT_EQ(rec.answers.size(), 3U);
  EXPECT_TRUE(rec.answers[0].polling);
  EXPECT_FALSE(rec.answers[1].polling);
  EXPECT_TRUE(rec.answers[2].polling);
}

TEST_F(HttpServerTest, PipelinedRequestsAreAnsweredInOrder) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/echo?a") + get_request("/later") + get_request("/echo?b")));
  EXPECT_EQ(c.read_response()->body, "GET /echo?a ");
  EXPECT_EQ(c.read_response()->body, "late");
  EXPECT_EQ(c.read_response()->body, "GET /echo?b ");
}

TEST_F(HttpServerTest, RequestValuesReachTheHandler) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send("POST /echo HTTP/1.1\r\nHost: x\r\nX-Test: yes\r\nContent-Length: 5\r\n\r\nhello"));
  EXPECT_EQ(c.read_response()->body, "POST /echo hello");
  ASSERT_TRUE(c.send(get_request("/header", "X-TEST: mixed case name\r\n")));
  EXPECT_EQ(c.read_response()->body, "mixed case name");
}

TEST_F(HttpServerTest, SixteenSimultaneousConnections) {
  start();
  std::vector<std::unique_ptr<RawClient>> clients;
  for (int i = 0; i < 16; ++i) clients.push_back(std::make_unique<RawClient>(port()));
  for (auto& c : clients) ASSERT_TRUE(c->send(get_request("/echo")));
  for (auto& c : clients) {
    const auto r = c->read_response();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
  EXPECT_EQ(server_->connections(), 16U);
}

TEST_F(HttpServerTest, HeaderOver8KiBIs431ThenClosed) {
  start();
  RawClient c(port());
  // The whole 100 KiB is sent before reading, as a client would; the server drops what it does not need.
  ASSERT_TRUE(c.send("GET /echo HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(100 * 1024, 'a') + "\r\n\r\n"));
  const auto r = c.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 431);
  EXPECT_EQ(r->get("connection"), "close");
  EXPECT_EQ(r->get("content-type"), "application/json");
  EXPECT_TRUE(c.wait_closed());
  EXPECT_TRUE(poll_until([&] { return server_->connections() == 0; }));
  EXPECT_EQ(recorded().answers.back().status, 431);
}

TEST_F(HttpServerTest, LongRequestLineIs431) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send("GET /" + std::string(9000, 'p') + " HTTP/1.1\r\nHost: x\r\n\r\n"));
  EXPECT_EQ(c.read_response()->status, 431);
}

TEST_F(HttpServerTest, HeaderJustUnder8KiBIsAccepted) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/echo", "X-Big: " + std::string(7 * 1024, 'a') + "\r\n")));
  EXPECT_EQ(c.read_response()->status, 200);
}

// Sends `header` and then `body_bytes` of body from a second thread, ignoring failures (the server
// may close while it sends); the test thread reads meanwhile.
class Sender {
 public:
  Sender(RawClient& c, std::string header, std::size_t body_bytes, bool chunked)
      : thread_([&c, header = std::move(header), body_bytes, chunked] {
          if (!c.send(header)) return;
          const std::string block(64 * 1024, 'b');
          char size_line[32];
          std::snprintf(size_line, sizeof size_line, "%zx\r\n", block.size());
          for (std::size_t sent = 0; sent < body_bytes; sent += block.size()) {
            const std::string piece = chunked ? std::string(size_line) + block + "\r\n" : block;
            if (!c.send(piece)) return;
          }
          if (chunked) c.send("0\r\n\r\n");
        }) {}
  ~Sender() { thread_.join(); }

 private:
  std::thread thread_;
};

TEST_F(HttpServerTest, HugeContentLengthIs413ReadableWhileTheClientStillSends) {
  start();
  RawClient c(port());
  std::optional<RawResponse> r;
  {
    Sender s(c, "POST /len HTTP/1.1\r\nHost: x\r\nContent-Type: text/plain\r\nContent-Length: 10000000000\r\n\r\n",
             4 * 1024 * 1024, false);
    r = c.read_response();
  }
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  EXPECT_EQ(r->get("connection"), "close");
  EXPECT_TRUE(c.wait_closed());
}

TEST_F(HttpServerTest, ChunkedBodyOver1MiBIs413ReadableWhileTheClientStillSends) {
  start();
  RawClient c(port());
  std::optional<RawResponse> r;
  {
    Sender s(c, "POST /len HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n", 2 * 1024 * 1024, true);
    r = c.read_response();
  }
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  EXPECT_EQ(r->get("connection"), "close");
  EXPECT_TRUE(c.wait_closed());
}

TEST_F(HttpServerTest, BodiesUpTo1MiBAreAccepted) {
  start();
  for (const bool chunked : {false, true}) {
    RawClient c(port());
    std::optional<RawResponse> r;
    {
      const std::string header = chunked ? "POST /len HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
                                         : "POST /len HTTP/1.1\r\nHost: x\r\nContent-Length: 1048576\r\n\r\n";
      Sender s(c, header, 1024 * 1024, chunked);
      r = c.read_response();
    }
    ASSERT_TRUE(r) << chunked;
    EXPECT_EQ(r->status, 200);
    EXPECT_EQ(r->body, "1048576");
  }
}

struct JunkCase {
  const char* name;
  std::string bytes;
};

class HttpJunk : public HttpServerTest, public ::testing::WithParamInterface<JunkCase> {};

TEST_P(HttpJunk, Is400ThenClosedAndTheServerStaysUp) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(GetParam().bytes));
  const auto r = c.read_response();
  ASSERT_TRUE(r) << GetParam().name;
  EXPECT_EQ(r->status, 400);
  EXPECT_EQ(r->get("connection"), "close");
  EXPECT_TRUE(c.wait_closed());
  RawClient next(port());
  ASSERT_TRUE(next.send(get_request("/echo")));
  EXPECT_EQ(next.read_response()->status, 200);
}

// A TLS 1.2 ClientHello's first bytes (record header, handshake header, version, random).
const std::string k_client_hello = std::string("\x16\x03\x01\x00\xc8\x01\x00\x00\xc4\x03\x03", 11) +
                                   std::string(32, '\x5a') + std::string("\x00\x00\x04\x13\x01\x00\xff\x01\x00", 9) +
                                   std::string(160, '\0');

INSTANTIATE_TEST_SUITE_P(
    Table, HttpJunk,
    ::testing::Values(JunkCase{"words", "HELLO WORLD\r\n\r\n"}, JunkCase{"no version", "GET /\r\n\r\n"},
                      JunkCase{"bad version", "GET / HTTP/9.9\r\n\r\n"}, JunkCase{"tls client hello", k_client_hello},
                      JunkCase{"bad header line", "GET / HTTP/1.1\r\nno colon here\r\n\r\n"},
                      JunkCase{"bad content-length", "POST / HTTP/1.1\r\nContent-Length: x\r\n\r\n"},
                      JunkCase{"two content-lengths",
                               "POST / HTTP/1.1\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n"},
                      JunkCase{"bad chunk", "POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n"}));

TEST_F(HttpServerTest, ExpectContinueGets100ThenTheAnswer) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send("POST /echo HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nContent-Length: 5\r\n\r\n"));
  const auto cont = c.read_response();
  ASSERT_TRUE(cont);
  EXPECT_EQ(cont->status, 100);
  ASSERT_TRUE(c.send("hello"));
  const auto r = c.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->body, "POST /echo hello");
  const auto rec = recorded();
  ASSERT_EQ(rec.answers.size(), 1U);  // 100 Continue is not an answer
}

TEST_F(HttpServerTest, ExpectContinueWithATooLargeBodyGets413AtOnce) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send("POST /echo HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nContent-Length: 2000000\r\n\r\n"));
  const auto r = c.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  EXPECT_TRUE(c.wait_closed());
}

TEST_F(HttpServerTest, ExpectContinueWithoutBodySendsNo100) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/echo", "Expect: 100-continue\r\n")));
  EXPECT_EQ(c.read_response()->status, 200);
}

TEST_F(HttpServerTest, HeadHasTheHeadersOfGetAndNoBody) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/echo")));
  const auto g = c.read_response();
  ASSERT_TRUE(c.send("HEAD /echo HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
  const auto h = c.read_response(true);
  ASSERT_TRUE(g && h);
  EXPECT_EQ(h->status, 200);
  // the router answers HEAD like GET; here the handler echoes the method, so the length differs by one
  EXPECT_EQ(h->get("content-length"), std::to_string(std::string("HEAD /echo ").size()));
  EXPECT_EQ(h->get("content-type"), g->get("content-type"));
  // no body bytes: the next response on the connection starts right away
  ASSERT_TRUE(c.send(get_request("/echo?next")));
  const auto n = c.read_response();
  ASSERT_TRUE(n);
  EXPECT_EQ(n->body, "GET /echo?next ");
  EXPECT_TRUE(c.pending().empty());
}

// The bytes of a response (the session formats them itself, as Beast's serializer would): status
// line, Server, Content-Type, the handler's fields in order, Content-Length, and a field value
// cannot end the header.
TEST_F(HttpServerTest, ResponseBytesAreTheStatusLineAndTheFieldsInOrder) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/fields")));
  const auto r = c.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->head,
            "HTTP/1.1 200 OK\r\nServer: mcemu\r\nContent-Type: text/plain\r\nCache-Control: no-store\r\n"
            "X-Echo: a    Injected: yes\r\nContent-Length: 2\r\n\r\n");
  EXPECT_EQ(r->body, "ok");
  ASSERT_TRUE(c.send("GET /nothing HTTP/1.0\r\nConnection: keep-alive\r\n\r\n"));
  const auto n = c.read_response();
  ASSERT_TRUE(n);
  EXPECT_EQ(n->head,
            "HTTP/1.0 404 Not Found\r\nServer: mcemu\r\nContent-Type: text/plain\r\nConnection: keep-alive\r\n"
            "Content-Length: 2\r\n\r\n");
  EXPECT_TRUE(c.pending().empty());
}

TEST_F(HttpServerTest, ResponseCloseEndsTheConnection) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/close")));
  const auto r = c.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->body, "bye");
  EXPECT_EQ(r->get("connection"), "close");
  EXPECT_TRUE(c.wait_closed());
}

TEST_F(HttpServerTest, ClientConnectionCloseAndHttp10AreHonoured) {
  start();
  {
    RawClient c(port());
    ASSERT_TRUE(c.send(get_request("/echo", "Connection: close\r\n")));
    EXPECT_EQ(c.read_response()->get("connection"), "close");
    EXPECT_TRUE(c.wait_closed());
  }
  {
    RawClient c(port());
    ASSERT_TRUE(c.send("GET /echo HTTP/1.0\r\n\r\n"));
    const auto r = c.read_response();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->head.substr(0, 8), "HTTP/1.0");
    EXPECT_TRUE(c.wait_closed());
  }
  {
    RawClient c(port());
    ASSERT_TRUE(c.send("GET /echo HTTP/1.0\r\nConnection: keep-alive\r\n\r\n"));
    EXPECT_EQ(c.read_response()->get("connection"), "keep-alive");
    ASSERT_TRUE(c.send(get_request("/echo")));
    EXPECT_EQ(c.read_response()->status, 200);
  }
}

TEST_F(HttpServerTest, AnswerLaterAndOnlyOnce) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/later") + get_request("/twice") + get_request("/echo")));
  EXPECT_EQ(c.read_response()->body, "late");
  EXPECT_EQ(c.read_response()->body, "first");
  EXPECT_EQ(c.read_response()->body, "GET /echo ");
}

TEST_F(HttpServerTest, HandlerExceptionIs500AndTheServerStaysUp) {
  start();
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/throw")));
  EXPECT_EQ(c.read_response()->status, 500);
  ASSERT_TRUE(c.send(get_request("/echo")));
  EXPECT_EQ(c.read_response()->status, 200);
}

TEST_F(HttpServerTest, IdleKeepAliveConnectionIsClosed) {
  HttpOptions o;
  o.idle_timeout = 150ms;
  start(o);
  RawClient c(port());
  ASSERT_TRUE(c.send(get_request("/echo")));
  EXPECT_EQ(c.read_response()->status, 200);
  EXPECT_TRUE(c.wait_closed());
  EXPECT_TRUE(poll_until([&] { return server_->connections() == 0; }));
  EXPECT_EQ(recorded().closed.size(), 1U);
}

// The idle timeout counts from the last request, not from the connection: requests every 100 ms
// keep a connection with a 300 ms idle timeout open for 600 ms, and it is closed once they stop.
TEST_F(HttpServerTest, EveryRequestMovesTheIdleDeadline) {
  HttpOptions o;
  o.idle_timeout = 300ms;
  start(o);
  RawClient c(port());
  for (int i = 0; i < 6; ++i) {
    ASSERT_TRUE(c.send(get_request("/echo")));
    ASSERT_EQ(c.read_response()->status, 200) << i;
    std::this_thread::sleep_for(100ms);
  }
  ASSERT_TRUE(c.send(get_request("/echo")));
  EXPECT_EQ(c.read_response()->status, 200) << "open after 600 ms of requests";
  EXPECT_TRUE(c.wait_closed());
  EXPECT_EQ(recorded().closed.size(), 1U);
}

TEST_F(HttpServerTest, DefaultLimitsAreTheSpecs) {
  const HttpOptions o;
  EXPECT_EQ(o.max_clients, 32U);
  EXPECT_EQ(o.header_limit, 8U * 1024U);
  EXPECT_EQ(o.body_limit, 1024U * 1024U);
  EXPECT_EQ(o.idle_timeout, 60s);
  EXPECT_EQ(o.linger, 1s);
  EXPECT_EQ(o.ws.max_clients, 16U);
  EXPECT_EQ(o.ws.period, 50ms);
  EXPECT_EQ(o.ws.ping_interval, 10s);
  EXPECT_EQ(o.ws.pong_timeout, 30s);
  EXPECT_EQ(o.ws.queue_limit, 1024U * 1024U);
}

TEST_F(HttpServerTest, StalledBodyIsClosedAfterTheBodyTimeout) {
  HttpOptions o;
  o.body_timeout = 150ms;
  start(o);
  RawClient c(port());
  ASSERT_TRUE(c.send("POST /len HTTP/1.1\r\nHost: x\r\nContent-Length: 10\r\n\r\nab"));
  EXPECT_TRUE(c.wait_closed());
}

TEST_F(HttpServerTest, OneMoreThanMaxClientsIsClosedAtOnce) {
  HttpOptions o;
  o.max_clients = 3;
  start(o);
  std::vector<std::unique_ptr<RawClient>> clients;
  for (int i = 0; i < 3; ++i) {
    clients.push_back(std::make_unique<RawClient>(port()));
    ASSERT_TRUE(clients.back()->send(get_request("/echo")));
    ASSERT_EQ(clients.back()->read_response()->status, 200);
  }
  RawClient extra(port());
  EXPECT_TRUE(extra.wait_closed());
  EXPECT_TRUE(extra.pending().empty());
  EXPECT_EQ(server_->connections(), 3U);
  clients[0]->close();
  ASSERT_TRUE(poll_until([&] { return server_->connections() == 2; }));
  RawClient again(port());
  ASSERT_TRUE(again.send(get_request("/echo")));
  EXPECT_EQ(again.read_response()->status, 200);
}

TEST_F(HttpServerTest, SlowlorisDoesNotBlockAnotherClient) {
  start();
  RawClient slow(port());
  const std::string request = get_request("/echo?slow");
  // one byte at a time, the header never complete while the other client is served
  for (std::size_t i = 0; i + 4 < request.size(); ++i) ASSERT_TRUE(slow.send(request.substr(i, 1)));
  RawClient other(port());
  ASSERT_TRUE(other.send(get_request("/echo?other")));
  const auto r = other.read_response();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->body, "GET /echo?other ");
  ASSERT_TRUE(slow.send(request.substr(request.size() - 4)));
  const auto s = slow.read_response();
  ASSERT_TRUE(s);
  EXPECT_EQ(s->body, "GET /echo?slow ");
}

TEST_F(HttpServerTest, SlowlorisIsClosedAtTheHeaderDeadline) {
  HttpOptions o;
  o.idle_timeout = 200ms;
  start(o);
  RawClient slow(port());
  ASSERT_TRUE(slow.send("GET /echo HTTP/1.1\r\nHo"));
  EXPECT_TRUE(slow.wait_closed());
}

TEST_F(HttpServerTest, ClientThatNeverReadsALargeResponseDoesNotBlockOthers) {
  HttpOptions o;
  o.write_timeout = 300ms;
  start(o);
  RawClient stuck(port(), 4096);
  ASSERT_TRUE(stuck.send(get_request("/big")));  // 32 MiB, never read
  for (int i = 0; i < 3; ++i) {
    RawClient other(port());
    ASSERT_TRUE(other.send(get_request("/echo")));
    const auto r = other.read_response();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
  // the stalled write hits its deadline and the connection is dropped
  EXPECT_TRUE(poll_until([&] { return server_->connections() == 0; }));
}

TEST_F(HttpServerTest, StopClosesEveryConnection) {
  start();
  RawClient a(port());
  RawClient b(port());
  ASSERT_TRUE(a.send(get_request("/echo")));
  ASSERT_EQ(a.read_response()->status, 200);
  ASSERT_TRUE(poll_until([&] { return server_->connections() == 2; }));
  server_->on_loop([this] {
    server_->server().stop();
    return 0;
  });
  EXPECT_TRUE(a.wait_closed());
  EXPECT_TRUE(b.wait_closed());
}

}  // namespace
}  // namespace mcemu::web::net::test
