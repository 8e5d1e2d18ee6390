#include "web/api/ws_protocol.hpp"

#include <array>
#include <nlohmann/json.hpp>

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

constexpr std::array<std::string_view, k_topic_count> k_topic_names = {"status", "scope", "trace", "udp"};

// nullopt when `j` is not an array of strings; unknown names are skipped.
std::optional<std::vector<Topic>> topic_list(const json& j) {
  if (!j.is_array()) return std::nullopt;
  std::vector<Topic> out;
  for (const auto& item : j) {
    if (!item.is_string()) return std::nullopt;
    if (const auto t = topic_from_string(item.get_ref<const std::string&>())) out.push_back(*t);
  }
  return out;
}

}  // namespace

std::string_view to_string(Topic t) { return k_topic_names[static_cast<std::size_t>(t)]; }

std::optional<Topic> topic_from_string(std::string_view name) {
  for (std::size_t i = 0; i < k_topic_names.size(); ++i) {
    if (k_topic_names[i] == name) return static_cast<Topic>(i);
  }
  return std::nullopt;
}

std::optional<ClientMessage> parse_client_message(std::string_view text) {
  const json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  const auto sub = j.find("subscribe");
  const auto unsub = j.find("unsubscribe");
  if (sub == j.end() && unsub == j.end()) return std::nullopt;
  ClientMessage m;
  if (sub != j.end()) {
    auto list = topic_list(*sub);
    if (!list) return std::nullopt;
    m.subscribe = std::move(*list);
  }
  if (unsub != j.end()) {
    auto list = topic_list(*unsub);
    if (!list) return std::nullopt;
    m.unsubscribe = std::move(*list);
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

void apply(Subscription& subscription, const ClientMessage& message) {
  for (const Topic t : message.subscribe) {
    subscription.add(t);
    if (t == Topic::trace) subscription.channels = message.channels.value_or(trace::ChannelSet{});
  }
  for (const Topic t : message.unsubscribe) subscription.remove(t);
}

bool apply_client_message(Subscription& subscription, std::string_view text) {
  const auto m = parse_client_message(text);
  if (!m) return false;
  apply(subscription, *m);
  return true;
}

std::string hello_message(std::string_view info_json) {
  std::string out = R"({"type":"hello","info":)";
  out += info_json.empty() ? std::string_view("{}") : info_json;
  out += '}';
  return out;
}

std::string udp_message(std::string_view text) {
  const nlohmann::ordered_json j = {{"type", "udp"}, {"text", std::string(text)}};
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace mcemu::web::api
