#include "web/api/http_util.hpp"

#include <array>
#include <cmath>
#include <cstdio>

#include "drive/od/hex.hpp"

namespace mcemu::web::api {

using nlohmann::json;

Response json_response(int status, const json& body) {
  Response r;
  r.status = status;
  r.body = dump_json(body);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response text_response(int status, std::string content_type, std::string body) {
  Response r;
  r.status = status;
  r.content_type = std::move(content_type);
  r.body = std::move(body);
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response error_json(int status, std::string_view code, std::string_view message) {
  return json_response(status, json{{"error", {{"code", code}, {"message", message}}}});
}

Response refusal_response(const device::Refusal& r) {
  switch (r.kind) {
    case device::Refusal::Kind::syntax: return error_json(400, "syntax", r.message);
    case device::Refusal::Kind::unavailable: return error_json(503, "unavailable", r.message);
    case device::Refusal::Kind::conflict: return error_json(409, "conflict", r.message);
    case device::Refusal::Kind::not_found: return error_json(404, "not-found", r.message);
    case device::Refusal::Kind::forbidden: break;
  }
  return error_json(403, "forbidden", r.message);
}

Response abort_response(od::AbortCode c) {
  const int status = (c == od::AbortCode::no_object || c == od::AbortCode::no_sub) ? 404 : 409;
  return json_response(
      status,
      json{{"error", {{"code", "abort"}, {"abortCode", abort_hex(c)}, {"message", std::string(od::description(c))}}}});
}

Response not_found_page() {
  Response r;
  r.status = 404;
  r.content_type = "text/html; charset=utf-8";
  r.body =
      "<!DOCTYPE html><html><head><title>404 Not Found</title></head><body><h1>404 Not Found</h1>"
      "<p>No such page. Go to <a href=\"/index.html\">the start page</a>.</p></body></html>\n";
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

std::optional<od::AbortCode> out_of_type_range(const od::EntryInfo* info, std::int64_t value) {
  if (!info || od::is_string(info->type)) return std::nullopt;
  if (info->access != od::Access::rw && info->access != od::Access::wo) return std::nullopt;
  const od::Range r = od::type_range(info->type);
  if (value >= r.min && value <= r.max) return std::nullopt;
  return value > r.max ? od::AbortCode::value_too_high : od::AbortCode::value_too_low;
}

Response range_error(const od::EntryInfo& info, std::int64_t value, od::AbortCode code) {
  const od::Range r = od::type_range(info.type);
  const std::string message = std::to_string(value) + " is outside " + std::string(od::to_string(info.type)) + " (" +
                              std::to_string(r.min) + " … " + std::to_string(r.max) + ")";
  return json_response(400, json{{"error", {{"code", "range"}, {"abortCode", abort_hex(code)}, {"message", message}}}});
}

Response unknown_api_path(std::string_view path) {
  return error_json(404, "not-found",
                    "no API route " + std::string(path) + " (GET /api/v1/openapi.json lists the routes)");
}

namespace {
std::string format_hex(const char* fmt, std::uint32_t v) {
  std::array<char, 16> buf{};
  std::snprintf(buf.data(), buf.size(), fmt, v);
  return buf.data();
}
}  // namespace

std::string hex_index(std::uint16_t index) { return format_hex("%04Xh", index); }
std::string hex_sub(std::uint8_t sub) { return format_hex("%02Xh", sub); }
std::string hex_u32(std::uint32_t v) { return format_hex("%08Xh", v); }
std::string h4(std::uint32_t v) { return format_hex("%04Xh", v); }
std::string abort_hex(od::AbortCode c) { return hex_u32(od::to_u32(c)); }

json scale_json(double scale) {
  if (std::isfinite(scale) && scale == std::floor(scale) && std::fabs(scale) < 1e15)
    return static_cast<std::int64_t>(scale);
  return scale;
}

json value_json(const od::Value& v) {
  if (const auto* n = std::get_if<std::int64_t>(&v)) return *n;
  return std::get<std::string>(v);
}

namespace {
char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Percent-decoding of one query component; nullopt for a malformed escape.
std::optional<std::string> decode_component(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%') {
      if (i + 2 >= s.size()) return std::nullopt;
      const int hi = od::hex_digit(s[i + 1]);
      const int lo = od::hex_digit(s[i + 2]);
      if (hi < 0 || lo < 0) return std::nullopt;
      out += static_cast<char>(hi * 16 + lo);
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}
}  // namespace

bool is_json_media_type(std::string_view content_type) {
  const auto semicolon = content_type.find(';');
  const std::string_view media = trim(content_type.substr(0, semicolon));
  constexpr std::string_view k_json = "application/json";
  if (media.size() != k_json.size()) return false;
  for (std::size_t i = 0; i < media.size(); ++i) {
    if (lower(media[i]) != k_json[i]) return false;
  }
  return true;
}

std::string_view target_path(std::string_view target) { return target.substr(0, target.find('?')); }

std::optional<std::map<std::string, std::string>> parse_query(std::string_view target) {
  std::map<std::string, std::string> out;
  const auto q = target.find('?');
  if (q == std::string_view::npos) return out;
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
    if (pair.empty()) continue;
    const auto eq = pair.find('=');
    auto key = decode_component(pair.substr(0, eq));
    auto value = decode_component(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1));
    if (!key || !value) return std::nullopt;
    if (!out.emplace(std::move(*key), std::move(*value)).second) return std::nullopt;
  }
  return out;
}

std::optional<json> json_object_body(const Request& r) {
  if (r.body.empty() && r.method == "POST") return json::object();
  json body = json::parse(r.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return std::nullopt;
  return body;
}

}  // namespace mcemu::web::api
