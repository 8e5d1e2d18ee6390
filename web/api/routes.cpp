#include "web/api/routes.hpp"

#include <algorithm>
#include <cctype>
#include <map>

namespace mcemu::web::api {

using nlohmann::json;

std::string_view to_string(Method m) {
  switch (m) {
    case Method::get: return "GET";
    case Method::put: return "PUT";
    case Method::post: return "POST";
    case Method::del: break;
  }
  return "DELETE";
}

std::optional<Method> method_of(std::string_view m) {
  if (m == "GET" || m == "HEAD") return Method::get;
  if (m == "PUT") return Method::put;
  if (m == "POST") return Method::post;
  if (m == "DELETE") return Method::del;
  return std::nullopt;
}

namespace {

std::vector<std::string_view> segments(std::string_view path) {
  std::vector<std::string_view> out;
  if (path.empty() || path[0] != '/') return out;
  path.remove_prefix(1);
  while (true) {
    const auto slash = path.find('/');
    out.push_back(path.substr(0, slash));
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);
  }
  return out;
}

bool is_parameter(std::string_view segment) {
  return segment.size() >= 2 && segment.front() == '{' && segment.back() == '}';
}

// What a path parameter is, by its name (the patterns use these names only).
std::string_view parameter_description(std::string_view name) {
  if (name == "index") return "object index, hexadecimal with or without h/0x (6041, 6041h, 0x6041)";
  if (name == "sub") return "sub-index, hexadecimal with or without h/0x (0, 01h)";
  if (name == "id") return "injection id as returned by POST /api/v1/faults (f7)";
  return "path parameter";
}

}  // namespace

// Segment by segment without allocating (the router asks every route on every request).
bool path_matches(std::string_view pattern, std::string_view path, std::vector<std::string>* values) {
  if (pattern.empty() || pattern[0] != '/' || path.empty() || path[0] != '/') return false;
  pattern.remove_prefix(1);
  path.remove_prefix(1);
  while (true) {
    const auto pslash = pattern.find('/');
    const auto sslash = path.find('/');
    const auto p = pattern.substr(0, pslash);
    const auto s = path.substr(0, sslash);
    if (is_parameter(p)) {
      if (values) values->emplace_back(s);
    } else if (p != s) {
      return false;
    }
    if ((pslash == std::string_view::npos) != (sslash == std::string_view::npos)) return false;
    if (pslash == std::string_view::npos) return true;
    pattern.remove_prefix(pslash + 1);
    path.remove_prefix(sslash + 1);
  }
}

std::optional<std::vector<std::string>> match_path(std::string_view pattern, std::string_view path) {
  std::vector<std::string> values;
  if (!path_matches(pattern, path, &values)) return std::nullopt;
  return values;
}

std::size_t parameter_count(std::string_view pattern) {
  if (pattern.empty() || pattern[0] != '/') return 0;
  pattern.remove_prefix(1);
  std::size_t n = 0;
  while (true) {
    const auto slash = pattern.find('/');
    n += is_parameter(pattern.substr(0, slash)) ? 1 : 0;
    if (slash == std::string_view::npos) return n;
    pattern.remove_prefix(slash + 1);
  }
}

std::vector<std::string> parameter_names(std::string_view pattern) {
  std::vector<std::string> out;
  for (const auto seg : segments(pattern)) {
    if (is_parameter(seg)) out.emplace_back(seg.substr(1, seg.size() - 2));
  }
  return out;
}

bool bearer_matches(std::optional<std::string_view> authorization, std::string_view token) {
  if (!authorization || token.empty()) return false;
  std::string_view a = *authorization;
  constexpr std::string_view scheme = "bearer ";
  if (a.size() < scheme.size()) return false;
  for (std::size_t k = 0; k < scheme.size(); ++k) {
    if (std::tolower(static_cast<unsigned char>(a[k])) != scheme[k]) return false;
  }
  a.remove_prefix(scheme.size());
  while (!a.empty() && a.front() == ' ') a.remove_prefix(1);
  while (!a.empty() && (a.back() == ' ' || a.back() == '\t')) a.remove_suffix(1);
  // every byte of the longer one is looked at: the time does not tell how much of a guess was right
  unsigned diff = a.size() == token.size() ? 0U : 1U;
  const std::size_t n = std::max(a.size(), token.size());
  for (std::size_t k = 0; k < n; ++k) {
    const auto x = k < a.size() ? static_cast<unsigned char>(a[k]) : 0U;
    const auto y = k < token.size() ? static_cast<unsigned char>(token[k]) : 0U;
    diff |= x ^ y;
  }
  return diff == 0;
}

json openapi_document(std::span<const RouteDoc> rows, std::string_view version) {
  json paths = json::object();
  for (const auto& r : rows) {
    json op{{"summary", r.summary}, {"operationId", std::string(to_string(r.method)) + " " + std::string(r.path)}};
    json params = json::array();
    for (const auto& name : parameter_names(r.path)) {
      params.push_back({{"name", name},
                        {"in", "path"},
                        {"required", true},
                        {"description", parameter_description(name)},
                        {"schema", {{"type", "string"}}}});
    }
    for (const auto& q : r.query) {
      params.push_back({{"name", q.name},
                        {"in", "query"},
                        {"required", false},
                        {"description", q.description},
                        {"schema", {{"type", q.type}}}});
    }
    if (!params.empty()) op["parameters"] = params;
    if (!r.body_type.empty()) {
      json schema = r.body_schema.empty() ? json::object() : json::parse(r.body_schema, nullptr, false);
      if (schema.is_discarded()) schema = json::object();
      op["requestBody"] = {{"required", r.method != Method::post}, {"content", {{r.body_type, {{"schema", schema}}}}}};
    }
    json responses = json::object();
    responses["200"] = {{"description", "OK"}, {"content", {{r.answer_type, json::object()}}}};
    if (r.token) {
      op["security"] = json::array({{{"bearer", json::array()}}});
      responses["401"] = {
          {"description", "mcemu was started with --api-token and the bearer token is missing or wrong"},
          {"content", {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}}}};
    }
    for (const auto& a : r.answers) {
      json answer{{"description", a.description}};
      if (a.status >= 300)
        answer["content"] = {{"application/json", {{"schema", {{"$ref", "#/components/schemas/Error"}}}}}};
      responses[std::to_string(a.status)] = answer;
    }
    op["responses"] = responses;
    std::string method(to_string(r.method));
    for (auto& c : method) c = static_cast<char>(c - 'A' + 'a');
    paths[std::string(r.path)][method] = op;
  }
  const json error_schema = {
      {"type", "object"},
      {"required", {"error"}},
      {"properties",
       {{"error",
         {{"type", "object"},
          {"required", {"code", "message"}},
          {"properties",
           {{"code",
             {{"type", "string"},
              {"description",
               "abort, syntax, range, content-type, method, not-found, conflict, unavailable, forbidden, "
               "unauthorized"}}},
            {"abortCode", {{"type", "string"}, {"description", "SDO abort code, e.g. 06090031h (code abort only)"}}},
            {"message", {{"type", "string"}}}}}}}}}};
  return json{{"openapi", "3.0.3"},
              {"info",
               {{"title", "mcemu JSON API"},
                {"version", version},
                {"description",
                 "The JSON API of the MovingCap emulator mcemu (web.md §8). Every state-changing POST needs "
                 "Content-Type: application/json; errors carry the body of components.schemas.Error."}}},
              {"paths", paths},
              {"components",
               {{"schemas", {{"Error", error_schema}}},
                {"securitySchemes",
                 {{"bearer",
                   {{"type", "http"},
                    {"scheme", "bearer"},
                    {"description", "only when mcemu runs with --api-token FILE (docs/security.md)"}}}}}}}};
}

}  // namespace mcemu::web::api
