// The page of shared memory (memfd) between the loop and one script engine process
// (scripting.md §10.2): the loop publishes drive time every step under a sequence counter (odd
// while writing, so a reader never sees a torn value); the runner's SIGUSR1 handler stores the
// current script line. Layout (little-endian), mirrored in scripting/runner/ipc.py:
//   0 u32 seq | 8 u64 time_ms | 16 u64 monotonic ns at that step (0: none) | 24 u32 flags
//   64 u32 line | 68 u32 line_seq
#pragma once

#include <cstdint>
#include <memory>

namespace mcemu::scripting {

class SharedPage {
 public:
  static constexpr std::size_t k_size = 4096;
  static constexpr std::uint32_t k_interpolate = 1;

  // A new page, or nullptr when memfd/mmap fail (errno set).
  static std::unique_ptr<SharedPage> create();
  ~SharedPage();
  SharedPage(const SharedPage&) = delete;
  SharedPage& operator=(const SharedPage&) = delete;

  int fd() const { return fd_; }
  void close_fd();  // once the child has its copy

  void publish_time(std::uint64_t time_ms, std::uint64_t mono_ns, bool interpolate);
  std::uint32_t line() const;
  std::uint32_t line_seq() const;

 private:
  SharedPage(int fd, void* map) : fd_(fd), map_(map) {}
  int fd_;
  void* map_;
};

}  // namespace mcemu::scripting
