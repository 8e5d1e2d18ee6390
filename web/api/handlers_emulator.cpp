// Router handlers of the emulator's own endpoints: trace and its exports, scope, LED, UDP
// console, runtime settings, clock and fault injection (web.md §8.6, §8.7, §8.9, §8.10, §9).
#include <charconv>

#include "sim/clock_mode.hpp"
#include "web/api/http_util.hpp"
#include "web/api/router.hpp"
#include "web/api/status.hpp"
#include "web/api/trace_export.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

constexpr std::size_t k_max_trace_limit = 10000;

Response bad(const std::string& message) { return error_json(400, "syntax", message); }
Response unavailable(const std::string& what) { return error_json(503, "unavailable", what); }

// A decimal query value in [min, max].
std::optional<std::uint64_t> query_uint(const std::string& text, std::uint64_t min, std::uint64_t max) {
  std::uint64_t v = 0;
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end || v < min || v > max) return std::nullopt;
  return v;
}

struct TraceQuery {
  trace::Ring::Query q;
  std::optional<std::uint64_t> conn;
};

// since, channels, limit and conn of the trace endpoints; an error names the parameter.
std::variant<TraceQuery, Response> trace_query(const std::map<std::string, std::string>& query, std::size_t limit,
                                               std::string_view default_channels) {
  TraceQuery t;
  t.q.limit = limit;
  const auto get = [&](const char* key) -> const std::string* {
    const auto it = query.find(key);
    return it == query.end() ? nullptr : &it->second;
  };
  if (const auto* s = get("since")) {
    const auto v = query_uint(*s, 0, UINT64_MAX);
    if (!v) return bad("\"since\": a sequence number (non-negative integer)");
    t.q.since = *v;
  }
  const std::string* channels = get("channels");
  const auto set = trace::parse_channels(channels ? std::string_view(*channels) : default_channels);
  if (!set || (channels && channels->empty())) {
    std::string names;
    for (std::size_t i = 0; i < trace::k_channel_count; ++i) {
      names += (i == 0 ? "" : ", ") + std::string(trace::to_string(static_cast<trace::Channel>(i)));
    }
    return bad("\"channels\": comma-separated names of " + names);
  }
  t.q.channels = *set;
  if (const auto* l = get("limit")) {
    const auto v = query_uint(*l, 1, k_max_trace_limit);
    if (!v) return bad("\"limit\": an integer 1 … 10000");
    t.q.limit = static_cast<std::size_t>(*v);
  }
  if (const auto* p = get("excludePolling")) {
    if (*p != "0" && *p != "1" && *p != "true" && *p != "false") return bad("\"excludePolling\": 1 or 0");
    t.q.exclude_polling = *p == "1" || *p == "true";
  }
  if (const auto* c = get("conn")) {
    const auto v = query_uint(*c, 1, UINT64_MAX);
    if (!v) return bad("\"conn\": a connection id (positive integer)");
    t.conn = *v;
  }
  return t;
}

std::vector<trace::Event> of_conn(std::vector<trace::Event> events, std::optional<std::uint64_t> conn) {
  if (conn) std::erase_if(events, [&](const trace::Event& e) { return e.conn != *conn; });
  return events;
}

}  // namespace

// ---- trace ------------------------------------------------------------------------------------

void Router::get_trace(const Ctx& c) {
  if (!services_.trace) return c.respond(unavailable("trace not available in this configuration"));
  auto t = trace_query(c.query, 500, "");
  if (auto* error = std::get_if<Response>(&t)) return c.respond(std::move(*error));
  c.respond(json_response(200, trace_json(services_.trace->query(std::get<TraceQuery>(t).q))));
}

void Router::get_trace_candump(const Ctx& c) {
  if (!services_.trace) return c.respond(unavailable("trace not available in this configuration"));
  auto t = trace_query(c.query, k_max_trace_limit, "slcan");
  if (auto* error = std::get_if<Response>(&t)) return c.respond(std::move(*error));
  const auto& tq = std::get<TraceQuery>(t);
  const auto events = of_conn(services_.trace->query(tq.q).events, tq.conn);
  c.respond(text_response(200, "text/plain; charset=utf-8", candump_log(events)));
}

void Router::get_trace_text(const Ctx& c) {
  if (!services_.trace) return c.respond(unavailable("trace not available in this configuration"));
  auto t = trace_query(c.query, k_max_trace_limit, "refgo,udp");
  if (auto* error = std::get_if<Response>(&t)) return c.respond(std::move(*error));
  const auto& tq = std::get<TraceQuery>(t);
  const auto events = of_conn(services_.trace->query(tq.q).events, tq.conn);
  c.respond(text_response(200, "text/plain; charset=utf-8", text_log(events)));
}

// ---- scope, LED, UDP --------------------------------------------------------------------------

void Router::get_scope(const Ctx& c) {
  std::uint64_t since = 0;
  if (const auto it = c.query.find("sinceMs"); it != c.query.end()) {
    const auto v = query_uint(it->second, 0, UINT64_MAX);
    if (!v) return c.respond(bad("\"sinceMs\": a drive time in ms (non-negative integer)"));
    since = *v;
  }
  c.respond(json_response(200, scope_json(device_.scope().since_ms(since))));
}

void Router::get_led(const Ctx& c) {
  // A FAULHABER MC has no Morse-coded STATUS LED (morse-led.md) but one bicolour status LED: its
  // state as the status snapshot's "led" gives it (status.hpp fh_led); no schedule, no edges.
  if (device_.personality().faulhaber) {
    const FhLed led = fh_led(device_.core().state());
    return c.respond(json_response(200, json{{"timeMs", device_.core().time_ms()},
                                             {"personality", device_.personality().name},
                                             {"color", led.color},
                                             {"blink", led.blink}}));
  }
  if (!services_.led) return c.respond(unavailable("LED model not available in this version"));
  const auto q = c.req.target.find('?');
  c.respond(services_.led(q == std::string::npos ? std::string_view() : std::string_view(c.req.target).substr(q + 1)));
}

void Router::get_udp(const Ctx& c) {
  if (!services_.udp) return c.respond(unavailable("UDP console view not available in this configuration"));
  const UdpView v = services_.udp();
  json listeners = json::array();
  for (const auto& l : v.listeners) {
    listeners.push_back({{"address", l.address},
                         {"port", l.port},
                         {"registeredMs", l.registered_ms},
                         {"registeredWall", l.registered_wall.empty() ? json(nullptr) : json(l.registered_wall)}});
  }
  c.respond(json_response(200, json{{"listeners", listeners},
                                    {"backlog", {{"bytes", v.backlog_bytes}, {"messages", v.backlog_messages}}},
                                    {"counters",
                                     {{"datagramsSent", v.datagrams_sent},
                                      {"datagramsDropped", v.datagrams_dropped},
                                      {"datagramsReceived", v.datagrams_received},
                                      {"ignoredPayloads", v.ignored_payloads}}},
                                    {"messages", v.messages}}));
}

// ---- settings, clock --------------------------------------------------------------------------

void Router::get_settings(const Ctx& c) { c.respond(json_response(200, settings_json(device_.settings()))); }

void Router::put_settings(const Ctx& c) {
  const auto body = json_object_body(c.req);
  if (!body) return c.respond(bad("expected a JSON object of settings"));
  const auto accepted = [&] { journal(c.req, "settings " + dump_json(*body)); };
  if (auto refused = device_.change_settings(*body, accepted)) return c.respond(refusal_response(*refused));
  c.respond(json_response(200, settings_json(device_.settings())));
}

void Router::get_clock(const Ctx& c) {
  const ClockInfo clock = clock_info();
  c.respond(json_response(
      200, json{{"mode", clock.mode}, {"scale", scale_json(clock.scale)}, {"timeMs", device_.core().time_ms()}}));
}

void Router::post_clock_advance(const Ctx& c) {
  const auto body = json_object_body(c.req);
  if (!body || !body->contains("ms")) return c.respond(bad("expected {\"ms\": 1 … 3600000}"));
  for (const auto& [key, value] : body->items()) {
    if (key != "ms") return c.respond(bad("\"" + key + "\": unknown field"));
  }
  const auto ms = json_uint((*body)["ms"], 1, sim::k_max_advance_ms);
  if (!ms) return c.respond(bad("\"ms\": an integer 1 … 3600000"));
  const ClockInfo clock = clock_info();
  if (clock.mode != "manual") {
    return c.respond(error_json(409, "conflict", "the clock is " + clock.mode + ", not manual (--clock manual)"));
  }
  if (!services_.advance_clock) return c.respond(unavailable("clock advance not available in this configuration"));
  journal(c.req, "clock advance " + std::to_string(*ms) + " ms");
  services_.advance_clock(*ms, [respond = c.respond](std::uint64_t time_ms) {
    respond(json_response(200, json{{"timeMs", time_ms}}));
  });
}

// ---- fault injection --------------------------------------------------------------------------

void Router::get_faults(const Ctx& c) { c.respond(json_response(200, device_.faults().list())); }

void Router::post_faults(const Ctx& c) {
  // The injection itself is journaled by FaultInjections (also removals by count or duration).
  auto outcome = device_.faults().create(c.req.body.empty() ? std::string("{}") : c.req.body);
  if (const auto* refused = std::get_if<device::Refusal>(&outcome)) return c.respond(refusal_response(*refused));
  c.respond(json_response(201, std::get<nlohmann::json>(outcome)));
}

void Router::delete_faults(const Ctx& c) {
  device_.faults().remove_all();
  c.respond(json_response(200, nlohmann::json{{"ok", true}}));
}

void Router::delete_fault(const Ctx& c) {
  if (const auto refused = device_.faults().remove(c.params[0])) return c.respond(refusal_response(*refused));
  c.respond(json_response(200, nlohmann::json{{"ok", true}}));
}

}  // namespace mcemu::web::api
