// Client messages of the WebSocket (web.md §10.1–10.2) and the server messages built without a source.
#include "web/api/ws_protocol.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace mcemu::web::api {
namespace {

Subscription subs(std::initializer_list<Topic> topics, trace::ChannelSet channels = {}) {
  Subscription s;
  s.topics = 0;
  for (auto t : topics) s.add(t);
  s.channels = channels;
  return s;
}

trace::ChannelSet channels(std::initializer_list<trace::Channel> list) {
  auto s = trace::ChannelSet::none();
  for (auto c : list) s.add(c);
  return s;
}

TEST(WsSubscription, DefaultIsStatusOnly) {
  const Subscription s;
  EXPECT_TRUE(s.has(Topic::status));
  EXPECT_FALSE(s.has(Topic::scope));
  EXPECT_FALSE(s.has(Topic::trace));
  EXPECT_FALSE(s.has(Topic::udp));
}

struct MessageCase {
  const char* text;
  Subscription before;
  bool applied;
  Subscription after;
};

class WsClientMessages : public ::testing::TestWithParam<MessageCase> {};

TEST_P(WsClientMessages, Apply) {
  const auto& c = GetParam();
  Subscription s = c.before;
  EXPECT_EQ(apply_client_message(s, c.text), c.applied) << c.text;
  EXPECT_EQ(s, c.after) << c.text;
}

using enum Topic;
using trace::Channel;

INSTANTIATE_TEST_SUITE_P(
    Table, WsClientMessages,
    ::testing::Values(
        MessageCase{R"({"subscribe":["scope","udp"]})", subs({status}), true, subs({status, scope, udp})},
        MessageCase{R"({"subscribe":["status","scope","trace","udp"]})", subs({}), true,
                    subs({status, scope, trace, udp})},
        MessageCase{R"({"unsubscribe":["status"]})", subs({status}), true, subs({})},
        MessageCase{R"({"unsubscribe":["udp"]})", subs({status}), true, subs({status})},
        MessageCase{R"({"subscribe":["trace"],"channels":["refgo"]})", subs({status}), true,
                    subs({status, trace}, channels({Channel::refgo}))},
        MessageCase{R"({"subscribe":["trace"],"channels":["refgo","udp","http"]})", subs({}), true,
                    subs({trace}, channels({Channel::refgo, Channel::udp, Channel::http}))},
        // a new trace subscription without channels selects all again
        MessageCase{R"({"subscribe":["trace"]})", subs({trace}, channels({Channel::refgo})), true, subs({trace})},
        // channels without subscribing trace change nothing
        MessageCase{R"({"subscribe":["udp"],"channels":["refgo"]})", subs({}), true, subs({udp})},
        MessageCase{R"({"subscribe":["bogus","udp"]})", subs({}), true, subs({udp})},
        MessageCase{R"({"subscribe":["udp"],"unsubscribe":["status","udp"]})", subs({status}), true, subs({})},
        MessageCase{R"({"subscribe":[]})", subs({status}), true, subs({status})},
        // ignored as a whole
        MessageCase{"not json", subs({status}), false, subs({status})},
        MessageCase{"", subs({status}), false, subs({status})},
        MessageCase{R"({"subscribe":["udp"])", subs({status}), false, subs({status})},
        MessageCase{R"(["subscribe"])", subs({status}), false, subs({status})},
        MessageCase{R"({"hello":1})", subs({status}), false, subs({status})},
        MessageCase{R"({"subscribe":"udp"})", subs({status}), false, subs({status})},
        MessageCase{R"({"subscribe":["udp",3]})", subs({status}), false, subs({status})},
        MessageCase{R"({"unsubscribe":{"a":1}})", subs({status}), false, subs({status})},
        MessageCase{R"({"subscribe":["trace"],"channels":["nope"]})", subs({}), false, subs({})},
        MessageCase{R"({"subscribe":["trace"],"channels":"refgo"})", subs({}), false, subs({})},
        MessageCase{R"({"subscribe":["trace"],"channels":[1]})", subs({}), false, subs({})}));

TEST(WsMessages, Hello) {
  const auto j = nlohmann::json::parse(hello_message(R"({"model":"MC349"})"));
  EXPECT_EQ(j["type"], "hello");
  EXPECT_EQ(j["info"]["model"], "MC349");
  EXPECT_EQ(nlohmann::json::parse(hello_message(""))["info"], nlohmann::json::object());
}

TEST(WsMessages, UdpTextIsEscapedAndTypeComesFirst) {
  const std::string m = udp_message("Hello World from MovingCap!\r\n\"q\"");
  EXPECT_EQ(m, R"({"type":"udp","text":"Hello World from MovingCap!\r\n\"q\""})");
}

TEST(WsMessages, UdpInvalidUtf8IsReplacedNotThrown) {
  const auto j =
      nlohmann::json::parse(udp_message(std::string("a\xff\xfe"
                                                    "b",
                                                    4)));
  EXPECT_EQ(j["text"],
            "a\xEF\xBF\xBD\xEF\xBF\xBD"
            "b");
}

TEST(WsTopics, NamesRoundTrip) {
  for (auto t : {status, scope, trace, udp}) EXPECT_EQ(topic_from_string(to_string(t)), t);
  EXPECT_EQ(topic_from_string("Status"), std::nullopt);
}

}  // namespace
}  // namespace mcemu::web::api
