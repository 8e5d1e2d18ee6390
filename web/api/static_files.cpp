#include "web/api/static_files.hpp"

#include <string>

#include "web/assets/assets.hpp"

namespace mcemu::web::api {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

bool etag_matches(std::string_view header, std::string_view etag) {
  header = trim(header);
  if (header == "*") return true;
  while (!header.empty()) {
    const auto comma = header.find(',');
    auto tag = trim(header.substr(0, comma));
    if (tag.substr(0, 2) == "W/") tag.remove_prefix(2);
    if (!tag.empty() && tag == etag) return true;
    if (comma == std::string_view::npos) break;
    header.remove_prefix(comma + 1);
  }
  return false;
}

std::optional<Response> serve_asset(const Request& request) {
  if (request.method != "GET" && request.method != "HEAD") return std::nullopt;
  std::string_view path = request.target;
  path = path.substr(0, path.find_first_of("?#"));
  if (path == "/") path = "/index.html";
  const assets::Asset* asset = assets::find(path);
  if (!asset) return std::nullopt;

  Response r;
  r.content_type = std::string(asset->mime);
  if (asset->mime.substr(0, 9) == "text/html") {
    r.headers.emplace_back("Cache-Control", "no-store");
    r.body = std::string(asset->bytes);
    return r;
  }
  r.headers.emplace_back("ETag", std::string(asset->etag));
  r.headers.emplace_back("Cache-Control", "max-age=3600");
  if (const auto inm = request.header("if-none-match"); inm && etag_matches(*inm, asset->etag)) {
    r.status = 304;
    return r;
  }
  r.body = std::string(asset->bytes);
  return r;
}

}  // namespace mcemu::web::api
