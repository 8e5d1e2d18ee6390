#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

#include "protocols/faulhaber/config.hpp"

namespace mcemu::faulhaber {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) {
  throw std::invalid_argument("faulhaber." + key + ": " + why);
}

std::int64_t integer(const nlohmann::json& v, const std::string& key, std::int64_t lo, std::int64_t hi) {
  if (!v.is_number_integer()) bad(key, "must be an integer");
  const auto n = v.get<std::int64_t>();
  if (n < lo || n > hi) bad(key, "must be " + std::to_string(lo) + " … " + std::to_string(hi));
  return n;
}

// Keys of the same section that other parts of the personality read and check (max_clients: the
// server's connection limit of the TCP port, server/settings.cpp).
constexpr std::array<std::string_view, 5> k_other_keys = {"device_name", "serial", "autostart",
                                                          "basic_statements_per_ms", "max_clients"};

}  // namespace

FaulhaberConfig faulhaber_config_from_json(const nlohmann::json& section) {
  FaulhaberConfig c;
  if (!section.is_object()) throw std::invalid_argument("faulhaber: must be a JSON object");
  for (const auto& [key, v] : section.items()) {
    if (key == "node_id") {
      c.node_id = static_cast<std::uint8_t>(integer(v, key, 1, 255));
    } else if (key == "crc_check") {
      if (!v.is_boolean()) bad(key, "must be true or false");
      c.crc_check = v.get<bool>();
    } else if (key == "response_delay_ms") {
      c.port.response_delay = Millis(integer(v, key, 0, 10000));
    } else if (key == "queue_limit_bytes") {
      c.port.queue_limit_bytes = static_cast<std::size_t>(integer(v, key, 1024, 16 * 1024 * 1024));
    } else if (std::find(k_other_keys.begin(), k_other_keys.end(), key) == k_other_keys.end()) {
      bad(key, "unknown key");
    }
  }
  return c;
}

}  // namespace mcemu::faulhaber
