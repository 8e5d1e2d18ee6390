// The Morse code of the green STATUS LED (morse-led.md §3, §4): the ITU table for exactly the
// characters the message can contain, and the on/off schedule of one repetition of a text.
//
// Contract: pure. Durations are whole milliseconds of drive time; a schedule starts with an "on"
// element and ends with the 3-unit gap after the last character (repetitions follow each other with
// no other pause, §2.2), so it has an even number of elements.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::led {

// The dot/dash pattern of c (".-" …), or nullopt for a character outside the table of §4.
std::optional<std::string_view> morse_code(char c);

// One repetition of a message: element durations alternating on, off, on, …, starting with on.
struct Schedule {
  std::string text;
  std::uint32_t unit_ms = 0;
  std::vector<std::uint32_t> elements;  // ms
  std::vector<std::uint64_t> starts;    // offset of element i from the repetition start (ms)
  std::uint64_t cycle_ms = 0;           // sum of elements
  std::uint64_t on_ms = 0;              // sum of the on elements

  // The LED at `offset` ms (0 ≤ offset < cycle_ms) into the repetition.
  bool on_at(std::uint64_t offset) const;
  // Index of the element that contains `offset` (0 ≤ offset < cycle_ms).
  std::size_t element_at(std::uint64_t offset) const;
};

// Throws std::invalid_argument for an empty text or a character outside the table (it cannot occur
// in a message built by StatusLed).
Schedule make_schedule(std::string text, std::uint32_t unit_ms);

}  // namespace mcemu::led
