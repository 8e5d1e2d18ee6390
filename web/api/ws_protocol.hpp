// The client side of the WebSocket protocol of web.md §10: which message kinds a client has
// subscribed to, the parser of its text messages and the server messages that do not come from a
// data source (hello, udp). PURE.
//
// Client messages (one JSON object per text frame):
//   {"subscribe": ["status", "scope", "trace", "udp"], "channels": ["refgo", …]}
//   {"unsubscribe": [ … ]}
// Both keys may appear in one message (subscribe is applied first). Unknown topic names in a list are
// skipped; a message that is not JSON, not an object, has neither key, has a key that is not an array
// of strings, or has a "channels" that is not an array of known trace channel names is ignored as a
// whole. "channels" sets the trace filter when "trace" is subscribed; subscribing "trace" without it
// selects all channels. Of duplicate keys the last counts; other keys are skipped, however deep
// (read as events, no document is built).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trace/trace.hpp"

namespace mcemu::web::api {

enum class Topic : std::uint8_t { status, scope, trace, udp };
inline constexpr std::size_t k_topic_count = 4;
std::string_view to_string(Topic t);
std::optional<Topic> topic_from_string(std::string_view name);

struct Subscription {
  std::uint8_t topics = 1U << static_cast<unsigned>(Topic::status);  // default: status only (§10.2)
  trace::ChannelSet channels;                                        // trace filter, default all

  bool has(Topic t) const { return (topics >> static_cast<unsigned>(t)) & 1U; }
  void add(Topic t) { topics = static_cast<std::uint8_t>(topics | (1U << static_cast<unsigned>(t))); }
  void remove(Topic t) { topics = static_cast<std::uint8_t>(topics & ~(1U << static_cast<unsigned>(t))); }
  bool operator==(const Subscription&) const = default;
};

struct ClientMessage {
  std::vector<Topic> subscribe;
  std::vector<Topic> unsubscribe;
  std::optional<trace::ChannelSet> channels;
};

// nullopt for a message that is ignored (see the header comment).
std::optional<ClientMessage> parse_client_message(std::string_view text);
void apply(Subscription& subscription, const ClientMessage& message);
// Parses and applies; false (subscription unchanged) for an ignored message.
bool apply_client_message(Subscription& subscription, std::string_view text);

// {"type":"hello","info":<info_json>}; `info_json` is the §8.1 object as JSON text ("{}" when empty).
std::string hello_message(std::string_view info_json);
// {"type":"udp","text":"…"}; bytes that are not UTF-8 become U+FFFD.
std::string udp_message(std::string_view text);

}  // namespace mcemu::web::api
