#include "web/api/ws_protocol.hpp"

#include <array>
#include <nlohmann/json.hpp>

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

constexpr std::array<std::string_view, k_topic_count> k_topic_names = {"status", "scope", "trace", "udp"};

// One pass over the text with nlohmann-json's event parser (SAX): no document is built, so a
// message costs no allocation per value (a client may send up to the frame limit of web/net).
// Only the three keys of the top-level object are looked at; the value of any other key is
// skipped, however deep. As when the text is parsed into an object, the last of duplicate keys
// counts.
class MessageReader {
 public:
  using string_t = json::string_t;

  struct List {
    bool present = false;
    bool valid = true;  // an array of strings (of known channel names, for "channels")
    std::vector<Topic> topics;
    trace::ChannelSet channels = trace::ChannelSet::none();
  };
  List subscribe, unsubscribe, channels;

  bool null() { return scalar(); }
  bool boolean(bool) { return scalar(); }
  bool number_integer(json::number_integer_t) { return scalar(); }
  bool number_unsigned(json::number_unsigned_t) { return scalar(); }
  bool number_float(json::number_float_t, const string_t&) { return scalar(); }
  bool binary(json::binary_t&) { return scalar(); }
  bool string(string_t& s) {
    if (depth_ == 2 && list_) {
      if (list_ == &channels) {
        const auto c = trace::channel_from_string(s);
        if (c) {
          channels.channels.add(*c);
        } else {
          channels.valid = false;
        }
      } else if (const auto t = topic_from_string(s)) {
        list_->topics.push_back(*t);
      }
      return true;
    }
    return scalar();
  }
  bool start_object(std::size_t) {
    if (depth_ == 0) {  // the message itself
      ++depth_;
      return true;
    }
    return open();
  }
  bool end_object() { return close(); }
  bool start_array(std::size_t) {
    if (depth_ == 1 && current_) {  // the value of a known key: its list starts
      list_ = current_;
      ++depth_;
      return true;
    }
    return open();
  }
  bool end_array() { return close(); }
  bool key(string_t& k) {
    if (depth_ != 1) return true;
    current_ = k == "subscribe"     ? &subscribe
               : k == "unsubscribe" ? &unsubscribe
               : k == "channels"    ? &channels
                                    : nullptr;
    if (current_) {
      *current_ = List{};
      current_->present = true;
    }
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) { return false; }

 private:
  // A value that is not a list where a list is wanted, or not a string inside one.
  void wrong_kind() {
    if (depth_ == 1 && current_) current_->valid = false;
    if (depth_ == 2 && list_) list_->valid = false;
  }
  bool scalar() {
    if (depth_ == 0) return false;  // the message is not an object
    wrong_kind();
    return true;
  }
  bool open() {
    if (depth_ == 0) return false;  // the message is an array
    wrong_kind();
    ++depth_;
    return true;
  }
  bool close() {
    --depth_;
    if (depth_ == 1) list_ = nullptr;
    return true;
  }

  int depth_ = 0;            // 1: inside the message's object, 2: inside the value of one of its keys
  List* current_ = nullptr;  // the known key whose value comes next (depth 1)
  List* list_ = nullptr;     // the list being read (depth 2)
};

}  // namespace

std::string_view to_string(Topic t) { return k_topic_names[static_cast<std::size_t>(t)]; }

std::optional<Topic> topic_from_string(std::string_view name) {
  for (std::size_t i = 0; i < k_topic_names.size(); ++i) {
    if (k_topic_names[i] == name) return static_cast<Topic>(i);
  }
  return std::nullopt;
}

std::optional<ClientMessage> parse_client_message(std::string_view text) {
  MessageReader r;
  if (!json::sax_parse(text.begin(), text.end(), &r)) return std::nullopt;
  if (!r.subscribe.present && !r.unsubscribe.present) return std::nullopt;
  for (const auto* list : {&r.subscribe, &r.unsubscribe, &r.channels}) {
    if (list->present && !list->valid) return std::nullopt;
  }
  ClientMessage m;
  m.subscribe = std::move(r.subscribe.topics);
  m.unsubscribe = std::move(r.unsubscribe.topics);
  if (r.channels.present) m.channels = r.channels.channels;
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
