// The MC BASIC loader (faulhaber.md §9.1, §9.5): checks a whole program and compiles it to the
// compact form of program.hpp, or reports the first problem with its line and reason.
//
// Checked here: the size (≤ 4096 bytes; reported as line 0), every line's syntax, labels (unknown,
// duplicate), IF/ELSEIF/ELSE/ENDIF structure and nesting (≤ 15 levels), FOR/NEXT pairing (also
// against the IF blocks), and the GOTO rule: a GOTO's label lies in the same branch of the same IF
// block, or both at top level (a one-line `IF c THEN GOTO x` belongs to the line's own branch).
// A one-line `IF c THEN stmt` opens a block when the next line that is neither empty nor a comment
// begins with ELSEIF or ELSE. Problems are found in line order; label problems after the scan.
//
// Pure.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

#include "scripting/basic/program.hpp"

namespace mcemu::basic {

struct LoadError {
  std::uint32_t line = 0;  // 1-based; 0 = the program as a whole (its size)
  std::string message{};
  bool operator==(const LoadError&) const = default;
};

using LoadResult = std::variant<Program, LoadError>;

LoadResult load(std::string_view source);

}  // namespace mcemu::basic
