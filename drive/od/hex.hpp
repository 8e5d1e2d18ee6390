// Hexadecimal digits as the text interfaces write object indices, sub-indices and values
// (RefGo "OR6041,0", JSON API paths "6041h", state-file keys "6041.00"). Header-only and pure.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace mcemu::od {

// 0–15 for 0-9, a-f, A-F; -1 for any other character.
constexpr int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// One or more hex digits (no prefix or suffix) whose value is at most `max`; nullopt otherwise.
constexpr std::optional<std::uint64_t> parse_hex(std::string_view digits, std::uint64_t max) {
  if (digits.empty()) return std::nullopt;
  std::uint64_t v = 0;
  for (char c : digits) {
    const int d = hex_digit(c);
    if (d < 0 || v > (max >> 4)) return std::nullopt;
    v = v * 16 + static_cast<std::uint64_t>(d);
    if (v > max) return std::nullopt;
  }
  return v;
}

}  // namespace mcemu::od
