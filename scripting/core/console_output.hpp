// The script's console output as UDP console messages (udp-debug.md §4.3–§4.6): the "cooked"
// LF → CRLF conversion, message boundaries after each CRLF, the 50 ms rule for a partial line, and
// the exact bytes of the `code:` life-cycle lines.
//
// Pure and single-threaded; time is drive time in ms passed by the caller.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::scripting {

inline constexpr std::uint64_t k_partial_line_ms = 50;

class OutputCooker {
 public:
  // Bytes the script wrote at drive time `now_ms`; returns the messages completed by them.
  std::vector<std::string> write(std::string_view bytes, std::uint64_t now_ms);
  // The held partial line once 50 ms have passed since its first byte (else nothing).
  std::optional<std::string> on_step(std::uint64_t now_ms);
  // When on_step() next has something to do.
  std::optional<std::uint64_t> deadline_ms() const;
  bool holding() const { return !held_.empty(); }

 private:
  std::string held_;
  std::uint64_t held_since_ms_ = 0;
};

// "code: starting, script id: <id>\n\r" and its siblings (udp-debug.md §4.3, §4.6).
std::string starting_line(std::string_view id);
std::string compile_line(std::string_view id);
std::string execute_line(std::string_view id);
std::string unavailable_line(std::string_view id);
std::string failure_signal_line(int signal, std::string_view id);
std::string failure_exit_line(int status, std::string_view id);
// "code: <text>\n\r": mcemu's own word about the engine (no sandbox, --unsafe-scripts), before the
// drive's line it explains; `text` is one sentence without line ends.
std::string engine_note_line(std::string_view text);

}  // namespace mcemu::scripting
