// Byte layout of RefGo replies (refgo.md §3, §9.4, §10). Pure formatting, no state.
//
//   reply:        <echo> "\r\n" [ <answer> "\r\n" ] ">"
//   prompt only:  ">"                      (empty, unknown and over-long lines)
//   error:        <echo> "\r\n" <prefix> ",ERROR," <8 lower-case hex digits> "h\r\n>"
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "drive/od/abort_code.hpp"

namespace mcemu::refgo {

inline constexpr std::string_view k_prompt = ">";

std::string reply(std::string_view echo);
std::string reply(std::string_view echo, std::string_view answer);
std::string error_reply(std::string_view echo, std::string_view prefix, od::AbortCode code);
// The answer line of a failed OR/OW or command: "<prefix>,ERROR,<code>h".
std::string error_answer(std::string_view prefix, od::AbortCode code);

// "%08x": TPSR and abort codes.
std::string hex8(std::uint32_t v);
// Lower-case hex without leading zeros plus "h" (OR ...,h: "427h", "0h", "fffffff6h").
std::string hex_h(std::uint32_t v);

}  // namespace mcemu::refgo
