#include "persistence/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

namespace mcemu::persistence {

namespace fs = std::filesystem;

namespace {

std::string os_error(const std::string& what, const fs::path& p, int err) {
  return what + " " + p.string() + ": " + std::strerror(err);
}

bool ensure_directory(const fs::path& dir, std::string& error) {
  if (dir.empty()) return true;
  struct stat st {};
  if (::stat(dir.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return true;
    error = "state directory " + dir.string() + " is not a directory";
    return false;
  }
  if (!ensure_directory(dir.parent_path(), error)) return false;
  if (::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) {
    error = os_error("cannot create directory", dir, errno);
    return false;
  }
  return true;
}

}  // namespace

std::optional<std::string> write_atomically(const fs::path& path, std::string_view contents,
                                            const WriteOptions& options) {
  std::string error;
  const fs::path dir = path.parent_path();
  if (!ensure_directory(dir, error)) return error;
  fs::path tmp = path;
  tmp += ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return os_error("cannot create", tmp, errno);
  const auto fail = [&](const std::string& what) {
    const int err = errno;
    ::close(fd);
    ::unlink(tmp.c_str());
    return os_error(what, tmp, err);
  };
  std::size_t done = 0;
  while (done < contents.size()) {
    std::size_t chunk = contents.size() - done;
    if (options.chunk_delay.count() > 0) {
      chunk = std::min<std::size_t>(chunk, 256);
      std::this_thread::sleep_for(options.chunk_delay);
    }
    const ssize_t n = ::write(fd, contents.data() + done, chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail("cannot write");
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) return fail("cannot fsync");
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    return os_error("cannot close", tmp, err);
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    return os_error("cannot rename onto", path, err);
  }
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd < 0) return os_error("cannot open directory", dir, errno);
  const int rc = ::fsync(dfd);
  const int err = errno;
  ::close(dfd);
  if (rc != 0) return os_error("cannot fsync directory", dir, err);
  return std::nullopt;
}

std::optional<std::string> read_file(const fs::path& path, std::string& error) {
  error.clear();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno != ENOENT) error = os_error("cannot read", path, errno);
    return std::nullopt;
  }
  std::string out;
  char buf[8192];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = os_error("cannot read", path, errno);
      ::close(fd);
      return std::nullopt;
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return out;
}

WriteOptions write_options_from_environment() {
  WriteOptions o;
  if (const char* d = std::getenv("MCEMU_TEST_STORE_DELAY_US")) {
    o.chunk_delay = std::chrono::microseconds(std::strtoll(d, nullptr, 10));
  }
  return o;
}

}  // namespace mcemu::persistence
