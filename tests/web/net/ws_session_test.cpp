// The WebSocket /api/v1/ws end to end (web.md §10) with real Beast clients: handshake answers (101,
// 426, 403, 503), hello, subscriptions, the status period and its shared snapshot, newest-wins for a
// client that does not read, 1008 when the queue overflows, ping/pong and the message size limit.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/web/net/net_fixture.hpp"

namespace mcemu::web::net::test {
namespace {

using json = nlohmann::json;
using api::Topic;

json parse(const std::optional<std::string>& m) { return m ? json::parse(*m, nullptr, false) : json(); }
bool is_type(const std::string& m, const char* type) {
  const auto j = json::parse(m, nullptr, false);
  return j.is_object() && j.value("type", "") == type;
}

class WsTest : public ::testing::Test {
 protected:
  void start(HttpOptions o = {}) {
    server_ = std::make_unique<TestServer>(o, [](const api::Request&, api::Respond respond) {
      api::Response r;
      r.body = "{}";
      respond(r);
    });
    server_->on_loop([this] {
      WsSources s;
      s.info = [] { return std::string(R"({"emulator":"mcemu","model":"MC349"})"); };
      s.status = [this] {
        const auto seq = ++status_calls_;
        return R"({"type":"status","seq":)" + std::to_string(seq) + R"(,"pad":")" + std::string(status_pad_, 'p') +
               "\"}";
      };
      s.scope = [this] { return scope_ready_.exchange(false) ? std::string(R"({"type":"scope","pos":[1,2]})") : ""; };
      s.trace_message = [](std::span<const trace::Event> events, trace::ChannelSet) {
        json j{{"type", "trace"}, {"events", json::array()}};
        for (const auto& e : events) j["events"].push_back(e.text);
        return j.dump();
      };
      server_->server().ws_hub().set_sources(s);
      return 0;
    });
  }
  WsHub& hub() { return server_->server().ws_hub(); }
  std::size_t subscribers(Topic t) {
    return server_->on_loop([this, t] { return hub().subscriber_count(t); });
  }
  std::size_t ws_clients() {
    return server_->on_loop([this] { return hub().client_count(); });
  }
  std::size_t websockets() {
    return server_->on_loop([this] { return server_->server().websocket_count(); });
  }
  void publish_udp(const std::string& text, int times = 1) {
    server_->on_loop([this, text, times] {
      for (int i = 0; i < times; ++i) hub().publish_udp(text);
      return 0;
    });
  }
  std::unique_ptr<TestWs> connect(const std::vector<std::pair<std::string, std::string>>& headers = {}) {
    auto ws = std::make_unique<TestWs>(server_->port());
    EXPECT_EQ(ws->handshake(headers), 101);
    return ws;
  }
  std::uint16_t port() const { return server_->port(); }

  std::atomic<int> status_calls_{0};
  std::atomic<std::size_t> status_pad_{0};
  std::atomic<bool> scope_ready_{false};
  std::unique_ptr<TestServer> server_;
};

TEST_F(WsTest, HelloFirstThenStatusByDefault) {
  start();
  auto ws = connect();
  const auto hello = parse(ws->read());
  EXPECT_EQ(hello["type"], "hello");
  EXPECT_EQ(hello["info"]["model"], "MC349");
  const auto status = parse(ws->read());
  EXPECT_EQ(status["type"], "status");
  EXPECT_GE(status["seq"].get<int>(), 1);
}

TEST_F(WsTest, NoExtensionIsNegotiated) {
  start();
  TestWs ws(port());
  ASSERT_EQ(ws.handshake({{"Sec-WebSocket-Extensions", "permessage-deflate; client_max_window_bits"}}), 101);
  EXPECT_EQ(ws.response().count(http::field::sec_websocket_extensions), 0U);
  EXPECT_EQ(ws.response()[http::field::server], "mcemu");
  EXPECT_TRUE(ws.read());
}

TEST_F(WsTest, SubscribeAndUnsubscribe) {
  start();
  auto a = connect();
  auto b = connect();  // keeps status subscribed, so snapshots go on being made
  ASSERT_TRUE(a->write(R"({"subscribe":["udp"]})"));
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::udp) == 1; }));
  publish_udp("one\r\n");
  const auto udp = parse(a->read_until([](const std::string& m) { return is_type(m, "udp"); }));
  EXPECT_EQ(udp["text"], "one\r\n");

  ASSERT_TRUE(a->write(R"({"unsubscribe":["status"]})"));
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::status) == 1; }));
  const int c0 = status_calls_;
  ASSERT_TRUE(poll_until([&] { return status_calls_ >= c0 + 3; }));
  publish_udp("marker");
  int later_statuses = 0;
  const auto marker = a->read_until([&](const std::string& m) {
    if (is_type(m, "status") && json::parse(m)["seq"].get<int>() > c0) ++later_statuses;
    return is_type(m, "udp");
  });
  ASSERT_TRUE(marker);
  EXPECT_EQ(parse(marker)["text"], "marker");
  EXPECT_EQ(later_statuses, 0);
  // b never subscribed udp
  EXPECT_FALSE(b->read_until([](const std::string& m) { return is_type(m, "udp"); }, 300ms));
}

TEST_F(WsTest, StatusEveryPeriodOneSnapshotSharedByAllClients) {
  HttpOptions o;
  o.ws.period = 20ms;
  start(o);
  std::vector<std::unique_ptr<TestWs>> clients;
  for (int i = 0; i < 3; ++i) clients.push_back(connect());
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::status) == 3; }));
  const int s0 = status_calls_;  // from here on every period has three subscribers
  for (auto& c : clients) {
    std::vector<int> seqs;
    while (seqs.size() < 10) {
      const auto m = c->read();
      ASSERT_TRUE(m);
      if (!is_type(*m, "status")) continue;
      const int seq = json::parse(*m)["seq"];
      if (seq > s0) seqs.push_back(seq);
    }
    // one source call per period for all clients: each sees consecutive numbers (a call per client
    // would make them step by three)
    for (std::size_t i = 1; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], seqs[i - 1] + 1);
  }
}

TEST_F(WsTest, StatusIsNotSentFasterThanThePeriod) {
  HttpOptions o;
  o.ws.period = 20ms;
  start(o);
  auto ws = connect();
  int first = 0;
  std::chrono::steady_clock::time_point t0;
  for (;;) {
    const auto m = ws->read();
    ASSERT_TRUE(m);
    if (!is_type(*m, "status")) continue;
    const int seq = json::parse(*m)["seq"];
    if (first == 0) {
      first = seq;
      t0 = std::chrono::steady_clock::now();
    }
    if (seq == first + 10) break;
  }
  // ten periods later; the timer never fires early and a late period is not caught up in a burst
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 9 * 20ms - 20ms);
}

TEST_F(WsTest, NewestStatusWinsForAClientThatDoesNotRead) {
  HttpOptions o;
  o.ws.period = 10ms;
  start(o);
  status_pad_ = 512 * 1024;
  auto slow = connect();
  // 80 × 512 KiB = 40 MiB: far more than the socket buffers hold
  ASSERT_TRUE(poll_until([&] { return status_calls_ >= 80; }, 20s));
  EXPECT_EQ(ws_clients(), 1U);  // still open: status never overflows the queue
  const int calls = status_calls_;
  int received = 0;
  int last = 0;
  const auto newest = slow->read_until(
      [&](const std::string& m) {
        if (!is_type(m, "status")) return false;
        const int seq = json::parse(m)["seq"];
        EXPECT_GT(seq, last);
        last = seq;
        ++received;
        return seq >= calls;
      },
      20s);
  ASSERT_TRUE(newest);
  EXPECT_LT(received, calls);  // older snapshots were replaced, not queued
}

TEST_F(WsTest, QueueOverflowClosesWith1008) {
  start();
  auto ws = connect();
  ASSERT_TRUE(ws->write(R"({"subscribe":["udp"],"unsubscribe":["status"]})"));
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::udp) == 1; }));
  // 40 × 64 KiB in one go: the writer cannot drain between them, the 1 MiB limit is passed
  publish_udp(std::string(64 * 1024, 'u'), 40);
  ASSERT_TRUE(poll_until([&] { return ws_clients() == 0; }));
  int udp = 0;
  while (auto m = ws->read()) {
    if (is_type(*m, "udp")) ++udp;
  }
  EXPECT_FALSE(ws->timed_out());
  EXPECT_EQ(ws->error(), websocket::error::closed);
  EXPECT_EQ(ws->reason().code, websocket::close_code::policy_error);
  EXPECT_LE(udp, 17);  // at most the 1 MiB queued and the one in flight
  EXPECT_TRUE(poll_until([&] { return websockets() == 0; }));
}

TEST_F(WsTest, PingsAnsweredKeepTheClientNoPongClosesIt) {
  HttpOptions o;
  o.ws.ping_interval = 100ms;
  o.ws.pong_timeout = 800ms;  // generous: the reader must not miss it on a loaded machine
  o.ws.close_timeout = 300ms;
  start(o);
  auto reader = connect();
  auto silent = connect();  // never reads, so never answers a ping
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < 2400ms) ASSERT_TRUE(reader->read()) << "reader was closed";
  EXPECT_GE(reader->pings(), 3);
  ASSERT_TRUE(poll_until([&] { return websockets() == 1; }));  // the silent one is gone
  EXPECT_EQ(ws_clients(), 1U);
  while (silent->read()) {
  }
  EXPECT_FALSE(silent->timed_out());  // the server ended it
  EXPECT_TRUE(reader->read());
}

TEST_F(WsTest, SeventeenthWebSocketGets503) {
  start();  // default limit 16
  std::vector<std::unique_ptr<TestWs>> clients;
  for (int i = 0; i < 16; ++i) clients.push_back(connect());
  TestWs extra(port());
  EXPECT_EQ(extra.handshake(), 503);
  EXPECT_EQ(websockets(), 16U);
  clients.pop_back();
  ASSERT_TRUE(poll_until([&] { return websockets() == 15; }));
  TestWs again(port());
  EXPECT_EQ(again.handshake(), 101);
}

TEST_F(WsTest, WebSocketsCountTowardsTheConnectionLimit) {
  HttpOptions o;
  o.max_clients = 2;
  start(o);
  auto ws = connect();
  RawClient http(port());
  ASSERT_TRUE(http.send(get_request("/x")));
  ASSERT_TRUE(http.read_response());
  RawClient extra(port());
  EXPECT_TRUE(extra.wait_closed());
  EXPECT_TRUE(extra.pending().empty());
}

TEST_F(WsTest, NotAnUpgradeIs426AndTheConnectionStays) {
  start();
  RawClient c(port());
  const std::string key = "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
  for (const std::string& request : {
           get_request("/api/v1/ws"),
           get_request("/api/v1/ws?x=1",
                       "Connection: Upgrade\r\nUpgrade: websocket\r\n" + key + "Sec-WebSocket-Version: 8\r\n"),
           get_request("/api/v1/ws", "Connection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\n"),
           get_request("/api/v1/ws",
                       "Connection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Key: short\r\n"
                       "Sec-WebSocket-Version: 13\r\n"),
           std::string("POST /api/v1/ws HTTP/1.1\r\nHost: x\r\nContent-Length: 2\r\n\r\n{}"),
       }) {
    ASSERT_TRUE(c.send(request));
    const auto r = c.read_response();
    ASSERT_TRUE(r) << request;
    EXPECT_EQ(r->status, 426) << request;
    EXPECT_EQ(r->get("upgrade"), "websocket");
  }
  ASSERT_TRUE(c.send("HEAD /api/v1/ws HTTP/1.1\r\nHost: x\r\n\r\n"));
  EXPECT_EQ(c.read_response(true)->status, 426);
  EXPECT_EQ(websockets(), 0U);
}

TEST_F(WsTest, CrossSiteHandshakeIs403) {
  start();
  const std::string self_origin = "http://127.0.0.1:" + std::to_string(port());
  for (const auto& headers : std::vector<std::vector<std::pair<std::string, std::string>>>{
           {{"Origin", "http://evil.example"}},
           {{"Origin", "http://127.0.0.1:1"}},
           {{"Sec-Fetch-Site", "cross-site"}},
           {{"Sec-Fetch-Site", "same-site"}, {"Origin", self_origin}},
       }) {
    TestWs ws(port());
    EXPECT_EQ(ws.handshake(headers), 403) << headers[0].second;
  }
  EXPECT_EQ(websockets(), 0U);
  TestWs same(port());
  EXPECT_EQ(same.handshake({{"Origin", self_origin}, {"Sec-Fetch-Site", "same-origin"}}), 101);
}

TEST_F(WsTest, TooLargeClientMessageCloses1009) {
  HttpOptions o;
  o.ws.max_message = 1024;
  start(o);
  auto ws = connect();
  ASSERT_TRUE(ws->write(std::string(2000, 'x')));
  while (ws->read()) {
  }
  EXPECT_FALSE(ws->timed_out());
  EXPECT_EQ(ws->reason().code, websocket::close_code::too_big);
  EXPECT_TRUE(poll_until([&] { return websockets() == 0; }));
}

TEST_F(WsTest, InvalidClientMessagesAreIgnored) {
  start();
  auto ws = connect();
  for (const char* m : {"garbage", "[]", R"({"subscribe":"udp"})", R"({"jump":1})", "{"}) ASSERT_TRUE(ws->write(m));
  ASSERT_TRUE(ws->write(R"({"subscribe":["udp"]})"));
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::udp) == 1; }));
  publish_udp("still here");
  EXPECT_TRUE(ws->read_until([](const std::string& m) { return is_type(m, "udp"); }));
}

TEST_F(WsTest, TraceWithChannelFilterAndScope) {
  start();
  auto ws = connect();
  ASSERT_TRUE(ws->write(R"({"subscribe":["trace","scope"],"channels":["refgo"]})"));
  ASSERT_TRUE(poll_until([&] { return subscribers(Topic::trace) == 1 && subscribers(Topic::scope) == 1; }));
  server_->on_loop([this] {
    trace::Event e;
    e.channel = trace::Channel::udp;
    e.text = "udp line";
    hub().on_trace(e);
    e.channel = trace::Channel::refgo;
    e.text = "TP";
    hub().on_trace(e);
    return 0;
  });
  scope_ready_ = true;
  json trace_message;
  bool scope = false;
  EXPECT_TRUE(ws->read_until([&](const std::string& m) {
    if (is_type(m, "trace")) trace_message = json::parse(m);
    if (is_type(m, "scope")) scope = true;
    return scope && !trace_message.is_null();
  }));
  EXPECT_EQ(trace_message["events"], json::array({"TP"}));
}

TEST_F(WsTest, ObserverSeesTheUpgradeAndTheClose) {
  std::vector<int> statuses;
  std::vector<std::uint64_t> closed;
  HttpObserver obs;
  obs.answered = [&](const HttpObserver::Answer& a) { statuses.push_back(a.status); };
  obs.closed = [&](std::uint64_t c) { closed.push_back(c); };
  TestServer server(
      {}, [](const api::Request&, api::Respond respond) { respond({}); }, obs);
  {
    TestWs ws(server.port());
    ASSERT_EQ(ws.handshake(), 101);
    ASSERT_TRUE(ws.read());
    ws.stream().close(websocket::close_code::normal);
  }
  ASSERT_TRUE(poll_until([&] { return server.on_loop([&] { return closed.size(); }) == 1; }));
  EXPECT_EQ(server.on_loop([&] { return statuses; }), std::vector<int>{101});
}

}  // namespace
}  // namespace mcemu::web::net::test
