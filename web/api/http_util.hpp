// Helpers shared by the JSON API handlers (web.md §1.3, §1.4, §8): JSON responses and the error
// body of §8, the upper-case hex forms of the answers, the query string and body parsers.
// PURE: plain values only; nothing here throws on any input.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "device/json_fields.hpp"
#include "device/refusal.hpp"
#include "drive/od/abort_code.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/types.hpp"
#include "web/api/http_types.hpp"

namespace mcemu::web::api {

// The JSON field readers of the bundle, shared by every handler.
using device::dump_json;
using device::json_hex_or_number;
using device::json_uint;
using device::parse_hex_token;

// An API answer: application/json, Cache-Control: no-store (web.md §1.4).
Response json_response(int status, const nlohmann::json& body);
// Text answers (EDS, trace exports).
Response text_response(int status, std::string content_type, std::string body);
// The error body of web.md §8: {"error": {"code": …, "message": …}}.
Response error_json(int status, std::string_view code, std::string_view message);
// A refusal of the bundle with its status and error code (web.md §8): syntax 400, unavailable 503,
// conflict 409, not_found 404, forbidden 403.
Response refusal_response(const device::Refusal& r);
// An OD refusal: 404 for a missing object or sub-index, 409 for every other code (web.md §8).
Response abort_response(od::AbortCode c);
// The strict range rule of the JSON API (object-dictionary.md §3.2): a number outside the data type
// of a writable numeric entry is refused with the code of the range check (06090031h above,
// 06090032h below) — never stored as its two's complement. nullopt when the value fits, or when the
// entry is missing, a string or not writable (the dictionary's earlier checks answer those).
std::optional<od::AbortCode> out_of_type_range(const od::EntryInfo* info, std::int64_t value);
// Its answer: 400, code "range", the abort code and the type's range in the message.
Response range_error(const od::EntryInfo& info, std::int64_t value, od::AbortCode code);

// The 404 page of web.md §1.4 (HTML, links to /index.html) for a path outside /api/.
Response not_found_page();
// The 404 of web.md §1.4 for a path under /api/ that no route matches: the JSON error body
// {"error": {"code": "not-found", "message": "no API route …"}}.
Response unknown_api_path(std::string_view path);

// Hex forms of web.md §8: "607Ah", "0Ah", "06090031h", and H4 of §4.2 ("0427h", at least 4 digits).
std::string hex_index(std::uint16_t index);
std::string hex_sub(std::uint8_t sub);
std::string hex_u32(std::uint32_t v);
std::string h4(std::uint32_t v);
std::string abort_hex(od::AbortCode c);

// A clock scale as JSON: an integer when it is one (1, 0), else the number (0.5).
nlohmann::json scale_json(double scale);

// od::Value as JSON (integer or string).
nlohmann::json value_json(const od::Value& v);

// True if the Content-Type's media type is application/json (case-insensitive, parameters allowed).
bool is_json_media_type(std::string_view content_type);

// The path of a request target (without "?query").
std::string_view target_path(std::string_view target);
// The query parameters of a target, percent-decoded ("+" is a space); nullopt for a malformed
// escape or a repeated key.
std::optional<std::map<std::string, std::string>> parse_query(std::string_view target);

// The body of a request as a JSON object: an empty body of a POST counts as {} (web.md §1.3);
// anything that is not a JSON object is nullopt.
std::optional<nlohmann::json> json_object_body(const Request& r);

}  // namespace mcemu::web::api
