// The route table's value types (one row per method and path of the JSON API, web.md §8), path
// matching with {parameters}, and the OpenAPI 3 document generated from the rows
// (GET /api/v1/openapi.json). PURE.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::web::api {

enum class Method : std::uint8_t { get, put, post, del };
std::string_view to_string(Method m);  // "GET", "PUT", "POST", "DELETE"
// "GET" and "HEAD" → get, …; nullopt for any other method.
std::optional<Method> method_of(std::string_view http_method);

struct QueryParam {
  std::string_view name;
  std::string_view type;  // "integer", "string"
  std::string_view description;
};

struct Answer {
  int status;
  std::string_view description;
};

// What the OpenAPI document says about one row.
struct RouteDoc {
  Method method = Method::get;
  std::string_view path{};  // "/api/v1/objects/{index}/{sub}"
  std::string_view summary{};
  std::vector<QueryParam> query{};  // the only query parameters accepted (others → 400)
  std::string_view body_type{};     // request media type ("" = no body)
  std::string_view body_schema{};   // JSON Schema of the body, as JSON text ("" = any)
  std::string_view answer_type = "application/json";
  std::vector<Answer> answers{};  // the statuses besides the default 200
  // An emulator endpoint that --api-token protects (docs/security.md): bearer security and 401.
  bool token = false;
};

// docs/security.md: the bearer token of --api-token is in `authorization` ("Bearer <token>",
// scheme case-insensitive); compared in time independent of where they differ.
bool bearer_matches(std::optional<std::string_view> authorization, std::string_view token);

// The values of the {parameters} of `pattern` if `path` matches it (a parameter matches one
// segment, also an empty one), else nullopt.
std::optional<std::vector<std::string>> match_path(std::string_view pattern, std::string_view path);
// The same test without allocating; the parameter values are appended to *values when given.
bool path_matches(std::string_view pattern, std::string_view path, std::vector<std::string>* values = nullptr);
// Number of {parameters} of a pattern (a literal segment beats a parameter).
std::size_t parameter_count(std::string_view pattern);
// The parameter names of a pattern, in order ("index", "sub").
std::vector<std::string> parameter_names(std::string_view pattern);

// The OpenAPI 3.0 document of the rows.
nlohmann::json openapi_document(std::span<const RouteDoc> rows, std::string_view version);

}  // namespace mcemu::web::api
