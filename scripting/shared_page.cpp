#include "scripting/shared_page.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace mcemu::scripting {

namespace {
template <typename T>
T* at(void* map, std::size_t offset) {
  return reinterpret_cast<T*>(static_cast<char*>(map) + offset);
}
}  // namespace

std::unique_ptr<SharedPage> SharedPage::create() {
  const int fd = memfd_create("mcemu-script-page", MFD_CLOEXEC);
  if (fd < 0) return nullptr;
  if (ftruncate(fd, static_cast<off_t>(k_size)) != 0) {
    ::close(fd);
    return nullptr;
  }
  void* map = mmap(nullptr, k_size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  if (map == MAP_FAILED) {
    ::close(fd);
    return nullptr;
  }
  std::memset(map, 0, k_size);
  return std::unique_ptr<SharedPage>(new SharedPage(fd, map));
}

SharedPage::~SharedPage() {
  munmap(map_, k_size);
  close_fd();
}

void SharedPage::close_fd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void SharedPage::publish_time(std::uint64_t time_ms, std::uint64_t mono_ns, bool interpolate) {
  auto* seq = at<volatile std::uint32_t>(map_, 0);
  const std::uint32_t s = *seq;
  *seq = s + 1;  // odd: writing
  std::atomic_thread_fence(std::memory_order_release);
  *at<volatile std::uint64_t>(map_, 8) = time_ms;
  *at<volatile std::uint64_t>(map_, 16) = mono_ns;
  *at<volatile std::uint32_t>(map_, 24) = interpolate ? k_interpolate : 0;
  std::atomic_thread_fence(std::memory_order_release);
  *seq = s + 2;
}

std::uint32_t SharedPage::line() const { return *at<volatile std::uint32_t>(map_, 64); }
std::uint32_t SharedPage::line_seq() const { return *at<volatile std::uint32_t>(map_, 68); }

}  // namespace mcemu::scripting
