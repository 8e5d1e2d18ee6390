#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "protocols/canopen/config.hpp"

namespace mcemu::canopen {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) {
  throw std::invalid_argument("canopen." + key + ": " + why);
}

std::int64_t integer(const nlohmann::json& v, const std::string& key, std::int64_t lo, std::int64_t hi) {
  if (!v.is_number_integer()) bad(key, "must be an integer");
  const auto n = v.get<std::int64_t>();
  if (n < lo || n > hi) bad(key, "must be " + std::to_string(lo) + " … " + std::to_string(hi));
  return n;
}

}  // namespace

CanopenConfig canopen_config_from_json(const nlohmann::json& section) {
  CanopenConfig c;
  if (!section.is_object()) throw std::invalid_argument("canopen: must be a JSON object");
  for (const auto& [key, v] : section.items()) {
    if (key == "sdo_timeout_ms") {
      c.sdo_timeout = std::chrono::milliseconds(integer(v, key, 1, 3600000));
    } else if (key == "sdo_block_size") {
      c.sdo_block_size = static_cast<int>(integer(v, key, 1, 127));
    } else if (key == "bootup_delay_ms") {
      if (!v.is_object()) bad(key, "must be an object with reset_node and reset_communication");
      for (const auto& [sub, d] : v.items()) {
        std::string k = key;
        k += '.';
        k += sub;
        if (sub == "reset_node") {
          c.bootup_delay_reset_node = std::chrono::milliseconds(integer(d, k, 0, 60000));
        } else if (sub == "reset_communication") {
          c.bootup_delay_reset_communication = std::chrono::milliseconds(integer(d, k, 0, 60000));
        } else {
          bad(k, "unknown key");
        }
      }
    } else if (key == "dynamic_pdo_mapping") {
      if (!v.is_boolean()) bad(key, "must be true or false");
      c.dynamic_pdo_mapping = v.get<bool>();
    } else {
      bad(key, "unknown key");
    }
  }
  return c;
}

}  // namespace mcemu::canopen
