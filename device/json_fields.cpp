#include "device/json_fields.hpp"

#include "drive/od/hex.hpp"

namespace mcemu::device {

using nlohmann::json;

std::string dump_json(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

std::optional<std::uint32_t> parse_hex_token(std::string_view t, std::uint32_t max) {
  if (t.size() >= 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
  } else if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
    t.remove_suffix(1);
  }
  if (t.size() > 8) return std::nullopt;
  const auto v = od::parse_hex(t, max);
  if (!v) return std::nullopt;
  return static_cast<std::uint32_t>(*v);
}

std::optional<std::uint32_t> json_hex_or_number(const json& v, std::uint32_t max) {
  if (v.is_string()) return parse_hex_token(v.get_ref<const std::string&>(), max);
  if (v.is_number_unsigned() && v.get<std::uint64_t>() <= max)
    return static_cast<std::uint32_t>(v.get<std::uint64_t>());
  return std::nullopt;
}

std::optional<std::uint64_t> json_uint(const json& v, std::uint64_t min, std::uint64_t max) {
  // Parsed text holds a non-negative integer as unsigned; a document built in code may hold it signed.
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0)) return std::nullopt;
  const auto n = v.get<std::uint64_t>();
  if (n < min || n > max) return std::nullopt;
  return n;
}

}  // namespace mcemu::device
