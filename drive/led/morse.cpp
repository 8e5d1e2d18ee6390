#include "drive/led/morse.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

namespace mcemu::led {
namespace {

// ITU-R M.1677-1 for the characters of §4: letters of MC, IP, ERR and the hex digits, digits, + and :.
constexpr std::array<std::pair<char, std::string_view>, 22> k_table = {{
    {'A', ".-"},    {'B', "-..."},  {'C', "-.-."},  {'D', "-.."},   {'E', "."},     {'F', "..-."},
    {'I', ".."},    {'M', "--"},    {'P', ".--."},  {'R', ".-."},   {'+', ".-.-."}, {':', "---..."},
    {'0', "-----"}, {'1', ".----"}, {'2', "..---"}, {'3', "...--"}, {'4', "....-"}, {'5', "....."},
    {'6', "-...."}, {'7', "--..."}, {'8', "---.."}, {'9', "----."},
}};

}  // namespace

std::optional<std::string_view> morse_code(char c) {
  for (const auto& [ch, code] : k_table) {
    if (ch == c) return code;
  }
  return std::nullopt;
}

bool Schedule::on_at(std::uint64_t offset) const { return element_at(offset) % 2 == 0; }

std::size_t Schedule::element_at(std::uint64_t offset) const {
  const auto it = std::upper_bound(starts.begin(), starts.end(), offset);
  return static_cast<std::size_t>(it - starts.begin()) - 1;
}

Schedule make_schedule(std::string text, std::uint32_t unit_ms) {
  if (text.empty()) throw std::invalid_argument("an empty Morse message");
  Schedule s;
  s.unit_ms = unit_ms;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto code = morse_code(text[i]);
    if (!code) throw std::invalid_argument(std::string("no Morse code for '") + text[i] + "'");
    for (std::size_t k = 0; k < code->size(); ++k) {
      s.elements.push_back(((*code)[k] == '-' ? 3 : 1) * unit_ms);
      // 1 unit between the elements of a character, 3 between characters and after the last one
      s.elements.push_back((k + 1 < code->size() ? 1 : 3) * unit_ms);
    }
  }
  std::uint64_t t = 0;
  for (std::size_t i = 0; i < s.elements.size(); ++i) {
    s.starts.push_back(t);
    t += s.elements[i];
    if (i % 2 == 0) s.on_ms += s.elements[i];
  }
  s.cycle_ms = t;
  s.text = std::move(text);
  return s;
}

}  // namespace mcemu::led
