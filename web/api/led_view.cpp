#include "web/api/led_view.hpp"

#include <charconv>
#include <optional>
#include <string>

namespace mcemu::web::api {
namespace {

using json = nlohmann::json;

Response json_reply(int status, const json& body) {
  Response r;
  r.status = status;
  r.body = body.dump();
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response syntax_error(const std::string& message) {
  return json_reply(400, json{{"error", {{"code", "syntax"}, {"message", message}}}});
}

json edges_json(const std::vector<led::Edge>& edges) {
  json a = json::array();
  for (const auto& [t, on] : edges) a.push_back(json::array({t, on}));
  return a;
}

std::optional<std::int64_t> parse_int(std::string_view text) {
  std::int64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc{} || p != end) return std::nullopt;
  return v;
}

}  // namespace

json led_state_json(const led::Leds& leds, std::uint64_t time_ms) {
  return json{{"green", leds.green.on(time_ms)}, {"yellow", leds.yellow.on(time_ms)}};
}

json led_json(const led::Leds& leds, std::uint64_t time_ms) {
  const auto v = leds.green.view(time_ms);
  json green{{"on", v.on},
             {"text", v.schedule->text},
             {"unitMs", v.schedule->unit_ms},
             {"cycleStartMs", v.cycle_start_ms},
             {"cycleMs", v.schedule->cycle_ms},
             {"elements", v.schedule->elements},
             {"nextText", v.next ? json(v.next->text) : json(nullptr)}};
  json yellow{{"on", leds.yellow.on(time_ms)},
              {"connections", leds.yellow.connections()},
              {"edges", edges_json(leds.yellow.edges(time_ms))}};
  return json{{"timeMs", time_ms}, {"green", std::move(green)}, {"yellow", std::move(yellow)}};
}

Response led_response(const led::Leds& leds, std::uint64_t time_ms, std::string_view query) {
  std::optional<std::string_view> from_text;
  std::optional<std::string_view> to_text;
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view item = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    const auto eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view{} : item.substr(eq + 1);
    if (key == "fromMs") from_text = value;
    if (key == "toMs") to_text = value;
  }
  json doc = led_json(leds, time_ms);
  if (!from_text && !to_text) return json_reply(200, doc);
  if (!from_text || !to_text) return syntax_error("fromMs and toMs go together");
  const auto from = parse_int(*from_text);
  const auto to = parse_int(*to_text);
  if (!from || !to) return syntax_error("fromMs and toMs are integers (ms of drive time)");
  // 0 ≤ B − A ≤ 600 000; with B ≥ A the unsigned difference is exact
  if (*to < *from ||
      static_cast<std::uint64_t>(*to) - static_cast<std::uint64_t>(*from) > led::StatusLed::k_max_window_ms) {
    return syntax_error("need 0 <= toMs - fromMs <= 600000");
  }
  doc["greenEdges"] = edges_json(leds.green.edges(time_ms, *from, *to));
  return json_reply(200, doc);
}

}  // namespace mcemu::web::api
