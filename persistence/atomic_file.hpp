// Crash-safe file replacement (persistence.md §10): temp file, full write, fsync, rename,
// directory fsync. Blocking; called on the persistence worker thread (and at shutdown).
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace mcemu::persistence {

struct WriteOptions {
  // Test hook of persistence.md §14 test 7: sleep this long between 256-byte chunks so that a
  // store can be interrupted by SIGKILL. Zero in production (env MCEMU_TEST_STORE_DELAY_US).
  std::chrono::microseconds chunk_delay{0};
};

// Replaces `path` atomically with `contents`, creating the parent directory (mode 0755) if needed.
// Returns an error text naming the path and the OS error, or nullopt on success. On failure the
// previous file is untouched and no temp file is left behind.
std::optional<std::string> write_atomically(const std::filesystem::path& path, std::string_view contents,
                                            const WriteOptions& options = {});

// Whole file, or nullopt with `error` set (ENOENT leaves `error` empty).
std::optional<std::string> read_file(const std::filesystem::path& path, std::string& error);

WriteOptions write_options_from_environment();

}  // namespace mcemu::persistence
