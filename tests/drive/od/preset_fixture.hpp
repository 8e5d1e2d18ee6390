// The model preset of a name, for the dictionary tests (one definition: the sanitizer tree compiles
// the test sources of an executable in unity batches, tests/CMakeLists.txt).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "drive/model/model_preset.hpp"

namespace mcemu::od::test {

inline model::ModelPreset preset(std::string_view name) {
  auto p = model::find_preset(name);
  if (!p) throw std::runtime_error("no preset " + std::string(name));
  return *p;
}

}  // namespace mcemu::od::test
