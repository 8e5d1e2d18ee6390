#include "scripting/core/console_output.hpp"

namespace mcemu::scripting {

std::vector<std::string> OutputCooker::write(std::string_view bytes, std::uint64_t now_ms) {
  std::vector<std::string> out;
  for (const char c : bytes) {
    if (held_.empty()) held_since_ms_ = now_ms;
    if (c == '\n') {
      held_ += "\r\n";
      out.push_back(std::move(held_));
      held_.clear();
    } else {
      held_ += c;
    }
  }
  return out;
}

std::optional<std::string> OutputCooker::on_step(std::uint64_t now_ms) {
  if (held_.empty() || now_ms < held_since_ms_ + k_partial_line_ms) return std::nullopt;
  std::string m = std::move(held_);
  held_.clear();
  return m;
}

std::optional<std::uint64_t> OutputCooker::deadline_ms() const {
  if (held_.empty()) return std::nullopt;
  return held_since_ms_ + k_partial_line_ms;
}

namespace {
std::string code_line(std::string_view what, std::string_view id) {
  return "code: " + std::string(what) + ", script id: " + std::string(id) + "\n\r";
}
}  // namespace

std::string starting_line(std::string_view id) { return code_line("starting", id); }
std::string compile_line(std::string_view id) { return code_line("compile", id); }
std::string execute_line(std::string_view id) { return code_line("execute", id); }
std::string unavailable_line(std::string_view id) { return code_line("engine unavailable", id); }
std::string failure_signal_line(int signal, std::string_view id) {
  return code_line("engine failure (signal " + std::to_string(signal) + ")", id);
}
std::string failure_exit_line(int status, std::string_view id) {
  return code_line("engine failure (exit status " + std::to_string(status) + ")", id);
}

std::string engine_note_line(std::string_view text) { return "code: " + std::string(text) + "\n\r"; }

}  // namespace mcemu::scripting
