// The plain HTTP request and response values exchanged between the Beast adapter (web/net) and
// the pure router (web/api). PURE: no sockets, no Beast types.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mcemu::web::api {

struct Request {
  std::string method;  // "GET", "HEAD", "POST", …
  std::string target;  // "/api/v1/info?x=1"
  std::string content_type;
  std::string body;
  // Every header as received, names lower-cased (Origin, Sec-Fetch-Site, Host, If-None-Match, …).
  std::vector<std::pair<std::string, std::string>> headers;
  std::uint64_t conn = 0;  // connection id, unique per HTTP server (trace, LINK/ACT LED)
  std::string peer;        // "127.0.0.1:53422"

  // The value of the first header named `lower_name` (lower case), if any.
  std::optional<std::string_view> header(std::string_view lower_name) const {
    const auto it = std::find_if(headers.begin(), headers.end(), [&](const auto& h) { return h.first == lower_name; });
    if (it == headers.end()) return std::nullopt;
    return std::string_view(it->second);
  }
};

// A request with only the first four fields set (tests, internal callers).
inline Request make_request(std::string method, std::string target, std::string content_type = {},
                            std::string body = {}) {
  Request r;
  r.method = std::move(method);
  r.target = std::move(target);
  r.content_type = std::move(content_type);
  r.body = std::move(body);
  return r;
}

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // extra headers (Allow, Cache-Control, ETag, …)
  bool close = false;  // send "Connection: close" and end the connection after this response
};

// Called exactly once per request, possibly after handle() has returned, on the loop thread.
using Respond = std::function<void(Response)>;

}  // namespace mcemu::web::api
