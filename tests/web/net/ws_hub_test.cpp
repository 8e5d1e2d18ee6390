// The WebSocket fan-out (web.md §10.3, §10.5) with fake clients; tick() is called directly, so these
// tests need no socket and no clock.
#include "web/net/ws_hub.hpp"

#include <gtest/gtest.h>

namespace mcemu::web::net {
namespace {

using api::Topic;

class FakeClient final : public WsClient {
 public:
  explicit FakeClient(std::initializer_list<Topic> topics, trace::ChannelSet channels = {}) {
    sub_.topics = 0;
    for (auto t : topics) sub_.add(t);
    sub_.channels = channels;
  }
  const api::Subscription& subscription() const override { return sub_; }
  void send_status(const api::WsOutbox::Message& m) override { statuses.push_back(m); }
  void send(const api::WsOutbox::Message& m) override { others.push_back(m); }

  api::Subscription sub_;
  std::vector<api::WsOutbox::Message> statuses;
  std::vector<api::WsOutbox::Message> others;
};

trace::Event event(trace::Channel c, std::string text) {
  trace::Event e;
  e.channel = c;
  e.text = std::move(text);
  return e;
}

trace::ChannelSet only(trace::Channel c) {
  auto s = trace::ChannelSet::none();
  s.add(c);
  return s;
}

class WsHubTest : public ::testing::Test {
 protected:
  WsHubTest() : hub_(io_) {
    WsSources s;
    s.info = [] { return std::string(R"({"model":"MC349"})"); };
    s.status = [this] { return R"({"type":"status","seq":)" + std::to_string(++status_calls_) + "}"; };
    s.scope = [this] {
      ++scope_calls_;
      return scope_next_;
    };
    s.trace_message = [this](std::span<const trace::Event> events, trace::ChannelSet channels) {
      trace_calls_.push_back({std::vector<trace::Event>(events.begin(), events.end()), channels});
      std::string out = R"({"type":"trace","n":)" + std::to_string(events.size()) + "}";
      return out;
    };
    hub_.set_sources(s);
  }

  boost::asio::io_context io_;  // never run: the period timer does not fire, tick() is called by hand
  WsHub hub_;
  int status_calls_ = 0;
  int scope_calls_ = 0;
  std::string scope_next_;
  std::vector<std::pair<std::vector<trace::Event>, trace::ChannelSet>> trace_calls_;
};

TEST_F(WsHubTest, OneStatusSnapshotPerPeriodSharedByAllSubscribers) {
  FakeClient a{Topic::status}, b{Topic::status}, c{Topic::udp};
  hub_.attach(a);
  hub_.attach(b);
  hub_.attach(c);
  hub_.tick();
  hub_.tick();
  EXPECT_EQ(status_calls_, 2);
  ASSERT_EQ(a.statuses.size(), 2U);
  ASSERT_EQ(b.statuses.size(), 2U);
  EXPECT_EQ(a.statuses[0].get(), b.statuses[0].get());  // the same immutable message, not a copy
  EXPECT_EQ(a.statuses[1].get(), b.statuses[1].get());
  EXPECT_EQ(*a.statuses[1], R"({"type":"status","seq":2})");
  EXPECT_TRUE(c.statuses.empty());
}

TEST_F(WsHubTest, NoStatusSubscriberNoSnapshot) {
  FakeClient a{Topic::udp};
  hub_.attach(a);
  hub_.tick();
  EXPECT_EQ(status_calls_, 0);
  EXPECT_EQ(scope_calls_, 0);
}

TEST_F(WsHubTest, EmptySourceTextSendsNothing) {
  FakeClient a{Topic::scope};
  hub_.attach(a);
  hub_.tick();
  EXPECT_EQ(scope_calls_, 1);
  EXPECT_TRUE(a.others.empty());
  scope_next_ = R"({"type":"scope"})";
  hub_.tick();
  ASSERT_EQ(a.others.size(), 1U);
  EXPECT_EQ(*a.others[0], scope_next_);
}

TEST_F(WsHubTest, UnsetSourcesSendNothing) {
  WsHub bare(io_);
  FakeClient a{Topic::status, Topic::scope, Topic::trace};
  bare.attach(a);
  bare.on_trace(event(trace::Channel::refgo, "x"));
  bare.tick();
  EXPECT_TRUE(a.statuses.empty());
  EXPECT_TRUE(a.others.empty());
  EXPECT_EQ(bare.hello_message(), R"({"type":"hello","info":{}})");
}

TEST_F(WsHubTest, HelloCarriesTheInfoSource) {
  EXPECT_EQ(hub_.hello_message(), R"({"type":"hello","info":{"model":"MC349"}})");
}

TEST_F(WsHubTest, TraceIsBatchedPerPeriodOneMessagePerDistinctFilter) {
  FakeClient all1{Topic::trace}, all2{Topic::trace}, refgo{{Topic::trace}, only(trace::Channel::refgo)},
      slcan{{Topic::trace}, only(trace::Channel::slcan)}, none{Topic::status};
  for (auto* c : {&all1, &all2, &refgo, &slcan, &none}) hub_.attach(*c);
  hub_.on_trace(event(trace::Channel::refgo, "OR6041"));
  hub_.on_trace(event(trace::Channel::udp, "hello"));
  hub_.on_trace(event(trace::Channel::refgo, "TP"));
  EXPECT_TRUE(trace_calls_.empty());  // nothing before the period ends
  hub_.tick();
  // all channels and refgo: one message each; slcan has no event this period, so no message
  ASSERT_EQ(trace_calls_.size(), 2U);
  EXPECT_EQ(trace_calls_[0].first.size(), 3U);
  EXPECT_EQ(trace_calls_[0].second, trace::ChannelSet{});
  ASSERT_EQ(trace_calls_[1].first.size(), 2U);
  EXPECT_EQ(trace_calls_[1].first[1].text, "TP");
  EXPECT_EQ(trace_calls_[1].second, only(trace::Channel::refgo));
  ASSERT_EQ(all1.others.size(), 1U);
  ASSERT_EQ(all2.others.size(), 1U);
  EXPECT_EQ(all1.others[0].get(), all2.others[0].get());
  ASSERT_EQ(refgo.others.size(), 1U);
  EXPECT_EQ(*refgo.others[0], R"({"type":"trace","n":2})");
  EXPECT_TRUE(slcan.others.empty());
  EXPECT_TRUE(none.others.empty());
  hub_.tick();  // the batch was consumed
  EXPECT_EQ(trace_calls_.size(), 2U);
}

TEST_F(WsHubTest, TraceIsDroppedAtOnceWithoutSubscriber) {
  FakeClient a{Topic::status};
  hub_.attach(a);
  hub_.on_trace(event(trace::Channel::refgo, "x"));
  a.sub_.add(Topic::trace);
  hub_.subscription_changed();
  hub_.tick();
  EXPECT_TRUE(trace_calls_.empty());  // the event came before anybody subscribed
}

TEST_F(WsHubTest, TraceBatchIsBounded) {
  WsOptions o;
  o.max_trace_batch = 3;
  WsHub hub(io_, o);
  std::size_t sent = 0;
  WsSources s;
  s.trace_message = [&](std::span<const trace::Event> e, trace::ChannelSet) {
    sent = e.size();
    return std::string("{}");
  };
  hub.set_sources(s);
  FakeClient a{Topic::trace};
  hub.attach(a);
  for (int i = 0; i < 5; ++i) hub.on_trace(event(trace::Channel::refgo, "x"));
  hub.tick();
  EXPECT_EQ(sent, 3U);
  EXPECT_EQ(hub.trace_dropped(), 2U);
}

TEST_F(WsHubTest, UdpGoesToUdpSubscribersAtOnce) {
  FakeClient a{Topic::udp}, b{Topic::status}, c{Topic::udp, Topic::status};
  for (auto* x : {&a, &b, &c}) hub_.attach(*x);
  hub_.publish_udp("Hello World from MovingCap!\r\n");
  ASSERT_EQ(a.others.size(), 1U);
  ASSERT_EQ(c.others.size(), 1U);
  EXPECT_EQ(a.others[0].get(), c.others[0].get());
  EXPECT_EQ(*a.others[0], R"({"type":"udp","text":"Hello World from MovingCap!\r\n"})");
  EXPECT_TRUE(b.others.empty());
}

TEST_F(WsHubTest, DetachedClientsGetNothing) {
  FakeClient a{Topic::status, Topic::udp};
  hub_.attach(a);
  EXPECT_EQ(hub_.client_count(), 1U);
  EXPECT_EQ(hub_.subscriber_count(Topic::status), 1U);
  hub_.detach(a);
  EXPECT_EQ(hub_.client_count(), 0U);
  EXPECT_EQ(hub_.subscriber_count(Topic::status), 0U);
  hub_.tick();
  hub_.publish_udp("x");
  EXPECT_TRUE(a.statuses.empty());
  EXPECT_TRUE(a.others.empty());
  EXPECT_EQ(status_calls_, 0);
}

TEST_F(WsHubTest, SubscriberCountsFollowChanges) {
  FakeClient a{Topic::status};
  hub_.attach(a);
  hub_.attach(a);  // attaching twice counts once
  EXPECT_EQ(hub_.client_count(), 1U);
  a.sub_.remove(Topic::status);
  a.sub_.add(Topic::scope);
  hub_.subscription_changed();
  EXPECT_EQ(hub_.subscriber_count(Topic::status), 0U);
  EXPECT_EQ(hub_.subscriber_count(Topic::scope), 1U);
}

}  // namespace
}  // namespace mcemu::web::net
