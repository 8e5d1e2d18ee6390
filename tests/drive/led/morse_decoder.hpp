// A standard Morse decoder for the LED tests (morse-led.md §7.1), independent of drive/led: its own
// ITU table, thresholds on ≤ 2 T → dot, else dash; off ≥ 2 T → character gap, off ≥ 5 T → word gap.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mcemu::led::test {

inline const std::map<std::string, char>& itu_table() {
  static const std::map<std::string, char> t = {
      {".-", 'A'},    {"-...", 'B'},  {"-.-.", 'C'},   {"-..", 'D'},    {".", 'E'},     {"..-.", 'F'},  {"--.", 'G'},
      {"....", 'H'},  {"..", 'I'},    {".---", 'J'},   {"-.-", 'K'},    {".-..", 'L'},  {"--", 'M'},    {"-.", 'N'},
      {"---", 'O'},   {".--.", 'P'},  {"--.-", 'Q'},   {".-.", 'R'},    {"...", 'S'},   {"-", 'T'},     {"..-", 'U'},
      {"...-", 'V'},  {".--", 'W'},   {"-..-", 'X'},   {"-.--", 'Y'},   {"--..", 'Z'},  {"-----", '0'}, {".----", '1'},
      {"..---", '2'}, {"...--", '3'}, {"....-", '4'},  {".....", '5'},  {"-....", '6'}, {"--...", '7'}, {"---..", '8'},
      {"----.", '9'}, {".-.-.", '+'}, {"---...", ':'}, {".-.-.-", '.'}, {"-...-", '='},
  };
  return t;
}

// Runs of (on, duration ms), alternating. Unknown patterns decode as '?'.
inline std::string decode_runs(const std::vector<std::pair<bool, std::uint64_t>>& runs, std::uint64_t unit_ms) {
  std::string out;
  std::string symbol;
  const auto flush = [&] {
    if (symbol.empty()) return;
    const auto it = itu_table().find(symbol);
    out += it == itu_table().end() ? '?' : it->second;
    symbol.clear();
  };
  for (const auto& [on, ms] : runs) {
    if (on) {
      symbol += ms <= 2 * unit_ms ? '.' : '-';
    } else if (ms >= 5 * unit_ms) {
      flush();
      out += ' ';
    } else if (ms >= 2 * unit_ms) {
      flush();
    }
  }
  flush();
  return out;
}

// Element durations alternating on/off, starting with on.
inline std::string decode_elements(const std::vector<std::uint32_t>& elements, std::uint64_t unit_ms) {
  std::vector<std::pair<bool, std::uint64_t>> runs;
  for (std::size_t i = 0; i < elements.size(); ++i) runs.emplace_back(i % 2 == 0, elements[i]);
  return decode_runs(runs, unit_ms);
}

// Run-length encoding of samples taken every 1 ms.
inline std::vector<std::pair<bool, std::uint64_t>> run_lengths(const std::vector<bool>& samples) {
  std::vector<std::pair<bool, std::uint64_t>> runs;
  for (bool s : samples) {
    if (runs.empty() || runs.back().first != s) {
      runs.emplace_back(s, 1);
    } else {
      ++runs.back().second;
    }
  }
  return runs;
}

}  // namespace mcemu::led::test
