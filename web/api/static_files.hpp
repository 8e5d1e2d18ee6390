// GET/HEAD of the embedded UI files (web.md §1.4, §2): `/` is `/index.html`; pages (text/html) are
// sent with `Cache-Control: no-store`; every other asset with its strong ETag and
// `Cache-Control: max-age=3600`, and 304 without a body when `If-None-Match` lists that ETag (weak
// comparison, RFC 9110 §13.1.2) or is `*`. The body of a HEAD answer is filled like GET's: the adapter
// sends its length and drops it. PURE.
#pragma once

#include <optional>
#include <string_view>

#include "web/api/http_types.hpp"

namespace mcemu::web::api {

// The answer for an asset, or nullopt when the method is not GET/HEAD or the path names no asset
// (the router then answers 404/405 itself). The query string is ignored.
std::optional<Response> serve_asset(const Request& request);

// true when the If-None-Match value `header` matches `etag` (a quoted strong ETag).
bool etag_matches(std::string_view header, std::string_view etag);

}  // namespace mcemu::web::api
