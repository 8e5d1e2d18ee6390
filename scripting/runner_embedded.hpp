// The Python runner of the script engine (scripting/runner/*.py), compiled into the binary
// (runner_embedded.cpp is generated at build time by embed_runner.cmake).
#pragma once

#include <span>
#include <string_view>

namespace mcemu::scripting {

struct RunnerModule {
  std::string_view name;    // "_mcemu_ipc", …: the name it is imported by
  std::string_view source;  // the Python text
};

// In bootstrap order: each module may import the ones before it; the last one's main() runs.
std::span<const RunnerModule> runner_modules();

}  // namespace mcemu::scripting
