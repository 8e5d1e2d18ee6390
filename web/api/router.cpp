#include "web/api/router.hpp"

#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "drive/od/hex.hpp"
#include "web/api/faults.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

std::string path_of(const std::string& target) {
  const auto q = target.find('?');
  return q == std::string::npos ? target : target.substr(0, q);
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t pos = 1;
  while (pos <= path.size()) {
    const auto slash = path.find('/', pos);
    const auto end = slash == std::string::npos ? path.size() : slash;
    parts.push_back(path.substr(pos, end - pos));
    pos = end + 1;
  }
  return parts;
}

Response json_response(int status, const json& body) {
  Response r;
  r.status = status;
  r.body = body.dump();
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response not_found() {
  Response r;
  r.status = 404;
  r.content_type = "text/html; charset=utf-8";
  r.body =
      "<!DOCTYPE html><html><head><title>404 Not Found</title></head><body><h1>404 Not Found</h1>"
      "<p>No such page. Go to <a href=\"/index.html\">the start page</a>.</p></body></html>\n";
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response error_json(int status, const std::string& code, const std::string& message) {
  return json_response(status, json{{"error", {{"code", code}, {"message", message}}}});
}

Response method_not_allowed(const std::string& allow) {
  auto r = error_json(405, "method", "method not allowed");
  r.headers.emplace_back("Allow", allow);
  return r;
}

std::string abort_hex(od::AbortCode c) {
  std::array<char, 16> buf{};
  std::snprintf(buf.data(), buf.size(), "%08Xh", od::to_u32(c));
  return buf.data();
}

// web.md §8: 404 for a missing object/sub-index, 409 for every other refusal.
Response abort_response(od::AbortCode c) {
  const int status = (c == od::AbortCode::no_object || c == od::AbortCode::no_sub) ? 404 : 409;
  return json_response(
      status,
      json{{"error", {{"code", "abort"}, {"abortCode", abort_hex(c)}, {"message", std::string(od::description(c))}}}});
}

json value_json(const od::Value& v) {
  if (std::holds_alternative<std::int64_t>(v)) return std::get<std::int64_t>(v);
  return std::get<std::string>(v);
}

std::string hex_index(std::uint16_t i) {
  std::array<char, 8> buf{};
  std::snprintf(buf.data(), buf.size(), "%04Xh", i);
  return buf.data();
}
std::string hex_sub(std::uint8_t s) {
  std::array<char, 8> buf{};
  std::snprintf(buf.data(), buf.size(), "%02Xh", s);
  return buf.data();
}

json info_json(const Info& i) {
  return json{{"emulator", "mcemu"},
              {"version", i.version},
              {"model", i.model},
              {"displayName", i.display_name},
              {"deviceName", i.device_name},
              {"softwareVersion", i.software_version},
              {"serial", i.serial},
              {"ip", i.ip},
              {"mask", i.mask},
              {"bind", i.bind},
              {"ports", {{"refgo", i.refgo_port}, {"slcan", i.slcan_port}, {"http", i.http_port}, {"udp", i.udp_port}}},
              {"stateDir", i.state_dir},
              {"scripting", {{"available", false}, {"engine", nullptr}}}};
}

bool is_json_content(const std::string& content_type) { return content_type.rfind("application/json", 0) == 0; }

}  // namespace

std::optional<std::uint32_t> parse_hex_token(std::string_view t, std::uint32_t max) {
  if (t.size() >= 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
  } else if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
    t.remove_suffix(1);
  }
  if (t.size() > 8) return std::nullopt;
  const auto v = od::parse_hex(t, max);
  if (!v) return std::nullopt;
  return static_cast<std::uint32_t>(*v);
}

Router::Router(od::ObjectDictionary& od, std::function<Info()> info,
               std::function<std::optional<od::Value>(std::uint16_t, std::uint8_t)> factory, FaultInjections* faults)
    : od_(od), info_(std::move(info)), factory_(std::move(factory)), faults_(faults) {}

void Router::handle(const Request& request, const Respond& respond) {
  const std::string path = path_of(request.target);
  const auto parts = split_path(path);
  const std::string& m = request.method;
  const bool get = m == "GET" || m == "HEAD";
  // web.md §1.3: state-changing POSTs must carry JSON (forces a CORS preflight).
  if (path.rfind("/api/", 0) == 0 && m == "POST" && !is_json_content(request.content_type)) {
    return respond(error_json(415, "content-type", "POST requests to /api/ need Content-Type: application/json"));
  }
  if (path == "/api/v1/info") {
    if (!get) return respond(method_not_allowed("GET, HEAD"));
    return respond(json_response(200, info_json(info_())));
  }
  const auto entry_json = [&](const od::EntryInfo& e) {
    json j{{"index", hex_index(e.index)},
           {"sub", hex_sub(e.sub)},
           {"name", e.name},
           {"type", od::to_string(e.type)},
           {"access", od::to_string(e.access)}};
    auto v = od_.read(e.index, e.sub);
    j["value"] = v ? value_json(*v) : json(nullptr);
    auto f = factory_ ? factory_(e.index, e.sub) : std::nullopt;
    j["factory"] = f ? value_json(*f) : value_json(e.factory);
    return j;
  };
  if (path == "/api/v1/objects") {
    if (!get) return respond(method_not_allowed("GET, HEAD"));
    json all = json::array();
    od_.for_each([&](const od::EntryInfo& e, const od::Value&) { all.push_back(entry_json(e)); });
    return respond(json_response(200, all));
  }
  if (path == "/api/v1/objects/read") {
    if (m != "POST") return respond(method_not_allowed("POST"));
    const json body = json::parse(request.body, nullptr, false);
    if (body.is_discarded() || !body.is_object() || !body.contains("objects") || !body["objects"].is_array()) {
      return respond(error_json(400, "syntax", "expected {\"objects\": [[index, sub], …]}"));
    }
    json values = json::array();
    for (const auto& item : body["objects"]) {
      std::optional<std::uint32_t> index;
      std::optional<std::uint32_t> sub;
      if (item.is_array() && item.size() == 2) {
        const auto token = [](const json& t, std::uint32_t max) -> std::optional<std::uint32_t> {
          if (t.is_string()) return parse_hex_token(t.get<std::string>(), max);
          if (t.is_number_unsigned() && t.get<std::uint64_t>() <= max)
            return static_cast<std::uint32_t>(t.get<std::uint64_t>());
          return std::nullopt;
        };
        index = token(item[0], 0xFFFF);
        sub = token(item[1], 0xFF);
      }
      if (!index || !sub) return respond(error_json(400, "syntax", "bad object reference " + item.dump()));
      auto v = od_.read(static_cast<std::uint16_t>(*index), static_cast<std::uint8_t>(*sub));
      values.push_back(v ? value_json(*v) : json{{"abortCode", abort_hex(v.error())}});
    }
    return respond(json_response(200, json{{"values", values}}));
  }
  if (parts.size() == 5 && parts[0] == "api" && parts[1] == "v1" && parts[2] == "objects") {
    const auto index = parse_hex_token(parts[3], 0xFFFF);
    const auto sub = parse_hex_token(parts[4], 0xFF);
    if (!index || !sub) return respond(error_json(400, "syntax", "object index and sub-index are hex numbers"));
    const auto i = static_cast<std::uint16_t>(*index);
    const auto s = static_cast<std::uint8_t>(*sub);
    if (get) {
      auto v = od_.read(i, s);
      if (!v) return respond(abort_response(v.error()));
      return respond(json_response(200, entry_json(*od_.info(i, s))));
    }
    if (m != "PUT") return respond(method_not_allowed("GET, HEAD, PUT"));
    const json body = json::parse(request.body, nullptr, false);
    if (body.is_discarded() || !body.is_object() || !body.contains("value") ||
        !(body["value"].is_number_integer() || body["value"].is_string())) {
      return respond(error_json(400, "syntax", "expected {\"value\": <integer or string>}"));
    }
    const od::Value value = body["value"].is_string() ? od::Value{body["value"].get<std::string>()}
                                                      : od::Value{body["value"].get<std::int64_t>()};
    auto finish = [this, i, s, respond](od::AbortCode c) {
      if (c != od::AbortCode::none) return respond(abort_response(c));
      auto v = od_.read(i, s);
      respond(json_response(200, json{{"ok", true}, {"value", v ? value_json(*v) : json(nullptr)}}));
    };
    const auto c = od_.write(i, s, value, od::Origin::web, finish);
    if (c != od::AbortCode::pending) finish(c);
    return;
  }
  if (faults_ && path == "/api/v1/faults") {
    if (m == "GET" || m == "HEAD") return respond(faults_->list());
    if (m == "POST") return respond(faults_->create(request.body));
    if (m == "DELETE") return respond(faults_->remove_all());
    return respond(method_not_allowed("GET, HEAD, POST, DELETE"));
  }
  if (faults_ && parts.size() == 4 && parts[0] == "api" && parts[1] == "v1" && parts[2] == "faults") {
    if (m != "DELETE") return respond(method_not_allowed("DELETE"));
    return respond(faults_->remove(parts[3]));
  }
  if (path == "/api/v1/store" || path == "/api/v1/factory-reset") {
    if (m != "POST") return respond(method_not_allowed("POST"));
    const bool store = path == "/api/v1/store";
    auto finish = [respond](od::AbortCode c) {
      if (c != od::AbortCode::none) return respond(abort_response(c));
      respond(json_response(200, json{{"ok", true}}));
    };
    const auto c = od_.write(store ? 0x1010 : 0x1011, 1, od::Value{std::int64_t{store ? 0x65766173 : 0x64616F6C}},
                             od::Origin::web, finish);
    if (c != od::AbortCode::pending) finish(c);
    return;
  }
  respond(not_found());
}

Response error_page(int status, const std::string& reason) {
  Response r;
  r.status = status;
  r.body = json{{"error", {{"code", "http"}, {"message", reason}}}}.dump();
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace mcemu::web::api
