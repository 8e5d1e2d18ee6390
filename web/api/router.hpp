// The HTTP request → response mapping of the web server, without any socket (web.md §1, §7, §8).
// PURE: the Beast adapter in web/net converts to and from these plain values.
//
// Served today: GET/HEAD /api/v1/info (§8.1); the object API of §8.3 (GET /api/v1/objects,
// GET/PUT /api/v1/objects/{index}/{sub}, POST /api/v1/objects/read); POST /api/v1/store and
// /api/v1/factory-reset (§7); the drive kinds of the fault-injection API (§9, web/api/faults.hpp). The pages of the web
// UI, the rest of the JSON API and the WebSocket belong to the web milestone; their paths answer 404 until then.
// Responses may complete later (a Store answers when the file is durable): handle() calls
// `respond` exactly once, possibly after it has returned, always on the event-loop thread.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "drive/od/dictionary.hpp"

namespace mcemu::web::api {

struct Request {
  std::string method;  // "GET", "HEAD", "POST", …
  std::string target;  // "/api/v1/info?x=1"
  std::string content_type;
  std::string body;
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;  // extra headers (Allow, Cache-Control, …)
};

using Respond = std::function<void(Response)>;

// What /api/v1/info reports (web.md §8.1).
struct Info {
  std::string version;
  std::string model;
  std::string display_name;
  std::string device_name;
  std::string software_version;
  std::uint32_t serial = 0;
  std::string ip;
  std::string mask;
  std::string bind;
  std::uint16_t refgo_port = 0;
  std::uint16_t slcan_port = 0;
  std::uint16_t http_port = 0;
  std::uint16_t udp_port = 0;
  std::string state_dir;
};

class FaultInjections;

class Router {
 public:
  // `factory` reads the factory value of an entry (the persistence factory image); `faults` serves
  // /api/v1/faults (web.md §9) when given.
  Router(od::ObjectDictionary& od, std::function<Info()> info,
         std::function<std::optional<od::Value>(std::uint16_t, std::uint8_t)> factory,
         FaultInjections* faults = nullptr);
  void handle(const Request& request, const Respond& respond);

 private:
  od::ObjectDictionary& od_;
  std::function<Info()> info_;
  std::function<std::optional<od::Value>(std::uint16_t, std::uint8_t)> factory_;
  FaultInjections* faults_;
};

// The bodies of the error responses the adapter produces itself (431, 413, 400).
Response error_page(int status, const std::string& reason);
// "6041", "6041h", "0x6041" → 0x6041; sub-indices likewise ("0", "01h").
std::optional<std::uint32_t> parse_hex_token(std::string_view text, std::uint32_t max);

}  // namespace mcemu::web::api
