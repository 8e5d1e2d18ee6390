#include "protocols/line/line_assembler.hpp"

namespace mcemu::line {

void LineAssembler::feed(std::string_view bytes, std::vector<Line>& out) {
  for (char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n' && last_was_cr_) {
      last_was_cr_ = false;
      continue;
    }
    last_was_cr_ = c == '\r';
    if (current_.raw.size() <= max_length_) current_.raw.push_back(ch);
    if (c == '\r' || c == '\n') {
      out.push_back(std::move(current_));
      current_ = Line{};
      continue;
    }
    const int kept = filter_(c);
    if (kept < 0 || current_.overlong) continue;
    if (current_.text.size() >= max_length_) {
      current_.overlong = true;
      continue;
    }
    current_.text.push_back(static_cast<char>(kept));
  }
}

void LineAssembler::reset() {
  current_ = Line{};
  last_was_cr_ = false;
}

}  // namespace mcemu::line
