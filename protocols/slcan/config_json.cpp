#include <nlohmann/json.hpp>
#include <stdexcept>

#include "protocols/slcan/config.hpp"

namespace mcemu::slcan {
namespace {

[[noreturn]] void bad(const std::string& key, const std::string& why) {
  throw std::invalid_argument("slcan." + key + ": " + why);
}

std::int64_t integer(const nlohmann::json& v, const std::string& key) {
  if (!v.is_number_integer()) bad(key, "must be an integer");
  return v.get<std::int64_t>();
}

}  // namespace

SlcanConfig slcan_config_from_json(const nlohmann::json& section) {
  SlcanConfig c;
  if (!section.is_object()) throw std::invalid_argument("slcan: must be a JSON object");
  for (const auto& [key, v] : section.items()) {
    if (key == "frame_ack") {
      const std::string s = v.is_string() ? v.get<std::string>() : std::string{};
      if (s == "z") {
        c.frame_ack = FrameAck::z;
      } else if (s == "cr") {
        c.frame_ack = FrameAck::cr;
      } else if (s == "none") {
        c.frame_ack = FrameAck::none;
      } else {
        bad(key, "must be \"z\", \"cr\" or \"none\"");
      }
    } else if (key == "version") {
      const std::string s = v.is_string() ? v.get<std::string>() : std::string{};
      bool ok = s.size() == 4;
      for (char ch : s) ok = ok && ch >= '0' && ch <= '9';
      if (!ok) bad(key, "must be a string of exactly 4 decimal digits");
      c.version = s;
    } else if (key == "serial_digits") {
      const auto n = integer(v, key);
      if (n != 4 && n != 8) bad(key, "must be 4 or 8");
      c.serial_digits = static_cast<int>(n);
    } else if (key == "max_clients") {
      const auto n = integer(v, key);
      if (n < 1 || n > 1024) bad(key, "must be 1 … 1024");
      c.max_clients = static_cast<int>(n);
    } else if (key == "queue_limit_bytes") {
      const auto n = integer(v, key);
      if (n < 1024) bad(key, "must be at least 1024");
      c.queue_limit_bytes = static_cast<std::size_t>(n);
    } else {
      bad(key, "unknown key");
    }
  }
  return c;
}

}  // namespace mcemu::slcan
