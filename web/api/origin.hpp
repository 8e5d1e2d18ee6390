// The cross-site check of web.md §1.3 for the requests that browsers could send from another web
// site without a CORS preflight: the WebSocket handshake (§10) and the real-drive endpoints of §6.
// A request is cross-site when it carries a `Sec-Fetch-Site` header other than `same-origin` or
// `none`, or an `Origin` header whose host and port differ from its `Host` header (an Origin that
// cannot be parsed, such as `null`, counts as different). Non-browser clients send neither header and
// pass. PURE.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "web/api/http_types.hpp"

namespace mcemu::web::api {

// host (lower case, IPv6 with its brackets) and port of an `Origin` or `Host` value.
struct Authority {
  std::string host;
  std::uint16_t port = 0;
  bool operator==(const Authority&) const = default;
};

// "http://Example.com:8080" → {example.com, 8080}; default ports from the scheme (http/ws 80,
// https/wss 443); nullopt for "null", a path, a missing scheme or an unknown scheme without a port.
std::optional<Authority> parse_origin(std::string_view origin);
// "localhost:8080", "[::1]", "Example.com" → host and port (80 when absent: mcemu speaks plain HTTP).
std::optional<Authority> parse_host(std::string_view host);

// true when web.md §1.3 refuses the request (403, no effect).
bool is_cross_site(const Request& request);
// The 403 answer of a refused request: §8 error body, code "cross-site".
Response cross_site_refused();

}  // namespace mcemu::web::api
