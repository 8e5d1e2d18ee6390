#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo {

namespace {
constexpr char k_hex[] = "0123456789abcdef";
}

std::string reply(std::string_view echo) {
  std::string out;
  out.reserve(echo.size() + 3);
  out.append(echo).append("\r\n>");
  return out;
}

std::string reply(std::string_view echo, std::string_view answer) {
  std::string out;
  out.reserve(echo.size() + answer.size() + 5);
  out.append(echo).append("\r\n").append(answer).append("\r\n>");
  return out;
}

std::string error_answer(std::string_view prefix, od::AbortCode code) {
  std::string out(prefix);
  out.append(",ERROR,").append(hex8(od::to_u32(code))).append("h");
  return out;
}

std::string error_reply(std::string_view echo, std::string_view prefix, od::AbortCode code) {
  return reply(echo, error_answer(prefix, code));
}

std::string hex8(std::uint32_t v) {
  std::string out(8, '0');
  for (int i = 7; i >= 0; --i, v >>= 4) out[static_cast<std::size_t>(i)] = k_hex[v & 0xF];
  return out;
}

std::string hex_h(std::uint32_t v) {
  std::string digits;
  do {
    digits.insert(digits.begin(), k_hex[v & 0xF]);
    v >>= 4;
  } while (v != 0);
  return digits + "h";
}

}  // namespace mcemu::refgo
