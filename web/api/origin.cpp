#include "web/api/origin.hpp"

#include <cctype>
#include <charconv>

namespace mcemu::web::api {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool valid_host_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return std::isalnum(u) || c == '-' || c == '.' || c == '_' || c == '~' || c == '%';
}

// "host[:port]" or "[v6][:port]" with the port given or `default_port`.
std::optional<Authority> parse_authority(std::string_view s, std::optional<std::uint16_t> default_port) {
  if (s.empty()) return std::nullopt;
  std::string_view host;
  std::string_view rest;
  if (s.front() == '[') {
    const auto close = s.find(']');
    if (close == std::string_view::npos || close < 2) return std::nullopt;
    for (char c : s.substr(1, close - 1)) {
      if (!std::isxdigit(static_cast<unsigned char>(c)) && c != ':' && c != '.') return std::nullopt;
    }
    host = s.substr(0, close + 1);
    rest = s.substr(close + 1);
  } else {
    const auto colon = s.find(':');
    host = s.substr(0, colon);
    rest = colon == std::string_view::npos ? std::string_view{} : s.substr(colon);
    if (host.empty()) return std::nullopt;
    for (char c : host) {
      if (!valid_host_char(c)) return std::nullopt;
    }
  }
  Authority a{lower(host), 0};
  if (rest.empty()) {
    if (!default_port) return std::nullopt;
    a.port = *default_port;
    return a;
  }
  if (rest.front() != ':' || rest.size() < 2 || rest.size() > 6) return std::nullopt;
  unsigned port = 0;
  const auto digits = rest.substr(1);
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), port);
  if (ec != std::errc{} || end != digits.data() + digits.size() || port == 0 || port > 65535) return std::nullopt;
  a.port = static_cast<std::uint16_t>(port);
  return a;
}

}  // namespace

std::optional<Authority> parse_origin(std::string_view origin) {
  origin = trim(origin);
  const auto sep = origin.find("://");
  if (sep == std::string_view::npos) return std::nullopt;
  const std::string scheme = lower(origin.substr(0, sep));
  std::optional<std::uint16_t> default_port;
  if (scheme == "http" || scheme == "ws") default_port = 80;
  if (scheme == "https" || scheme == "wss") default_port = 443;
  auto rest = origin.substr(sep + 3);
  // RFC 6454 serialises an origin without a path; a trailing "/" is tolerated, anything else is not.
  if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);
  if (rest.find_first_of("/?#@ ") != std::string_view::npos) return std::nullopt;
  return parse_authority(rest, default_port);
}

std::optional<Authority> parse_host(std::string_view host) { return parse_authority(trim(host), 80); }

bool is_cross_site(const Request& request) {
  if (const auto site = request.header("sec-fetch-site")) {
    const std::string v = lower(trim(*site));
    if (v != "same-origin" && v != "none") return true;
  }
  if (const auto origin = request.header("origin")) {
    const auto o = parse_origin(*origin);
    const auto host = request.header("host");
    if (!o || !host) return true;
    const auto h = parse_host(*host);
    if (!h || !(*h == *o)) return true;
  }
  return false;
}

Response cross_site_refused() {
  Response r;
  r.status = 403;
  r.body =
      R"j({"error":{"code":"cross-site","message":"refused: the request comes from another web site (Origin or Sec-Fetch-Site)"}})j";
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace mcemu::web::api
