// Client messages of the WebSocket (web.md §10.1–10.2) and the server messages built without a source.
#include "web/api/ws_protocol.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

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

// The reading of a message as a document (the parser before it became an event parser): the
// meaning of a message, which the event parser must keep for every text.
std::optional<ClientMessage> parse_as_document(std::string_view text) {
  using json = nlohmann::json;
  const json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  const auto topics = [](const json& v) -> std::optional<std::vector<Topic>> {
    if (!v.is_array()) return std::nullopt;
    std::vector<Topic> out;
    for (const auto& item : v) {
      if (!item.is_string()) return std::nullopt;
      if (const auto t = topic_from_string(item.get_ref<const std::string&>())) out.push_back(*t);
    }
    return out;
  };
  const auto sub = j.find("subscribe");
  const auto unsub = j.find("unsubscribe");
  if (sub == j.end() && unsub == j.end()) return std::nullopt;
  ClientMessage m;
  if (sub != j.end()) {
    auto list = topics(*sub);
    if (!list) return std::nullopt;
    m.subscribe = *list;
  }
  if (unsub != j.end()) {
    auto list = topics(*unsub);
    if (!list) return std::nullopt;
    m.unsubscribe = *list;
  }
  if (const auto ch = j.find("channels"); ch != j.end()) {
    if (!ch->is_array()) return std::nullopt;
    auto set = trace::ChannelSet::none();
    for (const auto& item : *ch) {
      if (!item.is_string()) return std::nullopt;
      const auto c = trace::channel_from_string(item.get_ref<const std::string&>());
      if (!c) return std::nullopt;
      set.add(*c);
    }
    m.channels = set;
  }
  return m;
}

std::string describe(const std::optional<ClientMessage>& m) {
  if (!m) return "ignored";
  std::string s = "subscribe";
  for (auto t : m->subscribe) (s += ' ') += to_string(t);
  s += "; unsubscribe";
  for (auto t : m->unsubscribe) (s += ' ') += to_string(t);
  if (m->channels) {
    s += "; channels";
    for (std::size_t i = 0; i < trace::k_channel_count; ++i) {
      if ((m->channels->bits >> i) & 1U) (s += ' ') += trace::to_string(static_cast<trace::Channel>(i));
    }
  }
  return s;
}

// Texts a client could send, and some it should not: every key and kind of value at every place,
// duplicate keys, escapes, nesting, and texts cut short or with a byte changed.
class MessageGenerator {
 public:
  explicit MessageGenerator(unsigned seed) : rng_(seed) {}

  std::string next() {
    std::string s = pick(6) == 0 ? value(0) : object(0);
    if (pick(8) == 0 && !s.empty()) s.resize(pick(static_cast<unsigned>(s.size())));
    if (pick(8) == 0 && !s.empty()) s[pick(static_cast<unsigned>(s.size()))] = "{}[],:\"\\ 1a"[pick(11)];
    return s;
  }

 private:
  unsigned pick(unsigned n) { return std::uniform_int_distribution<unsigned>(0, n - 1)(rng_); }
  static std::string quoted(std::string_view text) {
    std::string s(1, '"');
    s.append(text);
    s.push_back('"');
    return s;
  }

  std::string name() {
    static constexpr const char* k_names[] = {"status", "scope", "trace",  "udp", "refgo",        "slcan", "http",
                                              "drive",  "api",   "STATUS", "",    "st\\u0061tus", "x",     "script"};
    return quoted(k_names[pick(std::size(k_names))]);
  }
  std::string key() {
    static constexpr const char* k_keys[] = {"subscribe", "unsubscribe", "channels", "type", "sub\\u0073cribe",
                                             "",          "Subscribe"};
    return quoted(k_keys[pick(std::size(k_keys))]);
  }
  std::string list(int depth) {
    std::string s = "[";
    const unsigned n = pick(5);
    for (unsigned i = 0; i < n; ++i) {
      if (i) s += ',';
      s += pick(5) == 0 ? value(depth + 1) : name();
    }
    return s + "]";
  }
  std::string value(int depth) {
    switch (pick(depth < 3 ? 8 : 5)) {
      case 0: return "null";
      case 1: return pick(2) ? "true" : "-12.5e3";
      case 2: return std::to_string(static_cast<int>(pick(2000)) - 1000);
      case 3:
      case 4: return name();
      case 5:
      case 6: return list(depth);
      default: return object(depth + 1);
    }
  }
  std::string object(int depth) {
    std::string s = "{";
    const unsigned n = pick(5);
    for (unsigned i = 0; i < n; ++i) {
      if (i) s += ',';
      s += key();
      s += ':';
      s += pick(3) ? list(depth) : value(depth);
    }
    return s + "}";
  }

  std::mt19937 rng_;
};

// The event parser means what the document parser meant, text for text.
TEST(WsClientMessageParser, MeansWhatTheDocumentMeant) {
  MessageGenerator gen(26);
  int applied = 0;
  for (int i = 0; i < 20000; ++i) {
    const std::string text = gen.next();
    const auto expected = parse_as_document(text);
    const auto got = parse_client_message(text);
    ASSERT_EQ(describe(got), describe(expected)) << text;
    applied += expected ? 1 : 0;
  }
  // the generator reaches both outcomes often
  EXPECT_GT(applied, 2000);
  EXPECT_LT(applied, 18000);
}

TEST(WsClientMessageParser, DuplicateKeysLastCounts) {
  EXPECT_EQ(describe(parse_client_message(R"({"subscribe":3,"subscribe":["udp"]})")), "subscribe udp; unsubscribe");
  EXPECT_FALSE(parse_client_message(R"({"subscribe":["udp"],"subscribe":3})"));
  EXPECT_EQ(describe(parse_client_message(R"({"subscribe":["trace"],"channels":["x"],"channels":["refgo"]})")),
            "subscribe trace; unsubscribe; channels refgo");
}

TEST(WsClientMessageParser, OtherKeysAreSkippedHoweverDeep) {
  std::string deep = R"({"subscribe":["udp"],"other":)";
  for (int i = 0; i < 10000; ++i) deep += R"([{"subscribe":)";
  deep += "1";
  for (int i = 0; i < 10000; ++i) deep += "}]";
  deep += "}";
  EXPECT_EQ(describe(parse_client_message(deep)), "subscribe udp; unsubscribe");
}

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
