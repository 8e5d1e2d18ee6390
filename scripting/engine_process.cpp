#include "scripting/engine_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "scripting/runner_embedded.hpp"

extern char** environ;

namespace mcemu::scripting {

namespace asio = boost::asio;

namespace {

constexpr int k_fd_runner = 3;
constexpr int k_fd_socket = 4;
constexpr int k_fd_page = 5;
constexpr std::size_t k_chunk = 64 * 1024;

std::string errno_text(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

void put_le(std::string& out, std::uint64_t v, int n) {
  for (int k = 0; k < n; ++k) out += static_cast<char>((v >> (8 * k)) & 0xFF);
}

int pidfd_open(pid_t pid) { return static_cast<int>(syscall(SYS_pidfd_open, pid, 0)); }

// Everything the child does between fork and exec: async-signal-safe calls only.
[[noreturn]] void child(pid_t parent, const char* python, char* const argv[], char* const envp[], int runner, int sock,
                        int page, int devnull, const char* workdir, rlim_t memory) {
  setpgid(0, 0);
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(125);  // mcemu died before the death signal was armed
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  for (int s = 1; s < NSIG; ++s) sigaction(s, &dfl, nullptr);  // SIGPIPE was ignored by mcemu
  const rlimit as{memory, memory};
  setrlimit(RLIMIT_AS, &as);
  const rlimit core{0, 0};
  setrlimit(RLIMIT_CORE, &core);
  const rlimit files{64, 64};
  setrlimit(RLIMIT_NOFILE, &files);
  setpriority(PRIO_PROCESS, 0, 10);
  // Move the sources above the targets first, so that no dup2 overwrites another source.
  const int r = fcntl(runner, F_DUPFD, 10);
  const int s = fcntl(sock, F_DUPFD, 10);
  const int p = fcntl(page, F_DUPFD, 10);
  const int n = fcntl(devnull, F_DUPFD, 10);
  if (r < 0 || s < 0 || p < 0 || n < 0) _exit(126);
  if (dup2(n, 0) < 0 || dup2(n, 1) < 0 || dup2(n, 2) < 0 || dup2(r, k_fd_runner) < 0 || dup2(s, k_fd_socket) < 0 ||
      dup2(p, k_fd_page) < 0) {
    _exit(126);
  }
  if (syscall(SYS_close_range, 6U, ~0U, 0U) != 0) {
    for (int fd = 6; fd < 4096; ++fd) close(fd);
  }
  if (chdir(workdir) != 0) _exit(126);
  execve(python, argv, envp);
  _exit(127);
}

}  // namespace

const std::string& bootstrap_program() {
  static const std::string k_program =
      "import os,sys,types\n"
      "d=os.pread(3,os.fstat(3).st_size,0);os.close(3);i=0\n"
      "while i<len(d):\n"
      " n=int.from_bytes(d[i:i+2],'little');i+=2;k=d[i:i+n].decode();i+=n\n"
      " n=int.from_bytes(d[i:i+4],'little');i+=4;m=types.ModuleType(k);sys.modules[k]=m\n"
      " exec(compile(d[i:i+n],'<mcemu:'+k+'>','exec'),m.__dict__);i+=n\n"
      "del d\n"
      "sys.modules[k].main()\n";
  return k_program;
}

const std::string& runner_container() {
  static const std::string k_container = [] {
    std::string out;
    for (const auto& m : runner_modules()) {
      put_le(out, m.name.size(), 2);
      out += m.name;
      put_le(out, m.source.size(), 4);
      out += m.source;
    }
    return out;
  }();
  return k_container;
}

std::shared_ptr<EngineProcess> EngineProcess::spawn(asio::io_context& io, const SpawnOptions& options,
                                                    std::string& error) {
  int sv[2] = {-1, -1};
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    error = errno_text("socketpair");
    return nullptr;
  }
  auto page = SharedPage::create();
  const int runner = memfd_create("mcemu-runner", MFD_CLOEXEC);
  const int devnull = open("/dev/null", O_RDWR | O_CLOEXEC);
  std::string workdir = (std::filesystem::temp_directory_path() / "mcemu-script-XXXXXX").string();
  const bool dir_ok = mkdtemp(workdir.data()) != nullptr;
  const auto cleanup = [&] {
    for (int fd : {sv[0], sv[1], runner, devnull}) {
      if (fd >= 0) close(fd);
    }
    if (dir_ok) rmdir(workdir.c_str());
  };
  if (!page || runner < 0 || devnull < 0 || !dir_ok) {
    error = errno_text("engine set-up");
    cleanup();
    return nullptr;
  }
  const std::string& code = runner_container();
  for (std::size_t done = 0; done < code.size();) {
    const ssize_t n = write(runner, code.data() + done, code.size() - done);
    if (n <= 0) {
      error = errno_text("writing the runner");
      cleanup();
      return nullptr;
    }
    done += static_cast<std::size_t>(n);
  }

  // Everything the child needs is prepared before fork (no allocation after it).
  std::string a0 = options.python, a1 = "-I", a2 = "-S", a3 = "-u", a4 = "-c", a5 = bootstrap_program();
  char* argv[] = {a0.data(), a1.data(), a2.data(), a3.data(), a4.data(), a5.data(), nullptr};
  std::string e0 = "PATH=/usr/bin:/bin", e1 = "LANG=C.UTF-8", e2 = "MALLOC_ARENA_MAX=1";
  char* envp[] = {e0.data(), e1.data(), e2.data(), nullptr};
  const rlim_t memory = static_cast<rlim_t>(std::max(32U, options.memory_mib)) * 1024 * 1024;
  const pid_t parent = getpid();

  const pid_t pid = fork();
  if (pid < 0) {
    error = errno_text("fork");
    cleanup();
    return nullptr;
  }
  if (pid == 0) child(parent, a0.c_str(), argv, envp, runner, sv[1], page->fd(), devnull, workdir.c_str(), memory);

  setpgid(pid, pid);  // also here, so that signals reach the group however the race goes
  close(sv[1]);
  close(runner);
  close(devnull);
  page->close_fd();
  const int pidfd = pidfd_open(pid);
  return std::shared_ptr<EngineProcess>(new EngineProcess(io, pid, pidfd, sv[0], std::move(page), std::move(workdir)));
}

EngineProcess::EngineProcess(asio::io_context& io, pid_t pid, int pidfd, int sock, std::unique_ptr<SharedPage> page,
                             std::string workdir)
    : io_(io), pid_(pid), socket_(io), page_(std::move(page)), workdir_(std::move(workdir)), chunk_(k_chunk) {
  boost::system::error_code ec;
  socket_.assign(asio::local::stream_protocol(), sock, ec);
  socket_.non_blocking(true, ec);
  if (pidfd >= 0) pidfd_.emplace(io, pidfd);
}

EngineProcess::~EngineProcess() {
  if (!reaped_) kill_and_reap();
}

std::optional<ipc::Message> EngineProcess::next(bool& error) {
  error = false;
  const auto d = ipc::decode(in_);
  if (d.error) {
    error = true;
    return std::nullopt;
  }
  if (!d.message) return std::nullopt;
  in_.erase(0, d.consumed);
  return std::move(d.message);
}

void EngineProcess::read_more(std::function<void()> on_data) {
  if (reading_ || eof_ || !socket_.is_open()) return;
  reading_ = true;
  socket_.async_read_some(asio::buffer(chunk_), [self = shared_from_this(), on_data = std::move(on_data)](
                                                    const boost::system::error_code& ec, std::size_t n) {
    self->reading_ = false;
    if (ec == asio::error::operation_aborted) return;
    if (ec) {
      self->eof_ = true;
    } else {
      self->in_.append(self->chunk_.data(), n);
    }
    on_data();
  });
}

void EngineProcess::read_available() {
  if (!socket_.is_open()) return;
  for (;;) {
    const ssize_t n = ::recv(socket_.native_handle(), chunk_.data(), chunk_.size(), MSG_DONTWAIT);
    if (n > 0) {
      in_.append(chunk_.data(), static_cast<std::size_t>(n));
      continue;
    }
    if (n == 0) eof_ = true;
    return;
  }
}

void EngineProcess::send(std::string frame) {
  if (!socket_.is_open()) return;
  if (!writing_ && out_.empty()) {
    const ssize_t n = ::send(socket_.native_handle(), frame.data(), frame.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n == static_cast<ssize_t>(frame.size())) return;
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) return;  // the process is gone
    frame.erase(0, n > 0 ? static_cast<std::size_t>(n) : 0);
  }
  out_ += frame;
  write_pending();
}

void EngineProcess::write_pending() {
  if (writing_ || out_.empty() || !socket_.is_open()) return;
  writing_ = true;
  auto data = std::make_shared<std::string>(std::move(out_));
  out_.clear();
  asio::async_write(socket_, asio::buffer(*data),
                    [self = shared_from_this(), data](const boost::system::error_code& ec, std::size_t) {
                      self->writing_ = false;
                      if (!ec) self->write_pending();
                    });
}

void EngineProcess::close_channel() {
  boost::system::error_code ec;
  socket_.close(ec);
  out_.clear();
}

void EngineProcess::signal_group(int sig) {
  if (!reaped_) ::kill(-pid_, sig);
}

void EngineProcess::kill_group() { signal_group(SIGKILL); }
void EngineProcess::stop_group() { signal_group(SIGSTOP); }
void EngineProcess::continue_group() { signal_group(SIGCONT); }
void EngineProcess::sample_line() {
  if (!reaped_) ::kill(pid_, SIGUSR1);
}

void EngineProcess::on_exit(std::function<void(int)> fn) {
  exit_fn_ = std::move(fn);
  if (exit_status_) {
    auto f = std::move(exit_fn_);
    f(*exit_status_);
    return;
  }
  watch_exit();
}

void EngineProcess::watch_exit() {
  if (reaped_) return;
  if (pidfd_) {
    pidfd_->async_wait(asio::posix::stream_descriptor::wait_read,
                       [self = shared_from_this()](const boost::system::error_code& ec) {
                         if (ec == asio::error::operation_aborted) return;
                         self->reap();
                       });
    return;
  }
  // No pidfd (kernel < 5.3): poll the child every 5 ms.
  auto timer = std::make_shared<asio::steady_timer>(io_, std::chrono::milliseconds(5));
  timer->async_wait([self = shared_from_this(), timer](const boost::system::error_code& ec) {
    if (!ec) self->reap();
  });
}

void EngineProcess::reap() {
  if (reaped_) return;
  // The leader's zombie still reserves the group id: end whatever the script started in it.
  ::kill(-pid_, SIGKILL);
  int status = 0;
  const pid_t r = waitpid(pid_, &status, WNOHANG);
  if (r == 0) {
    watch_exit();
    return;
  }
  reaped_ = true;
  if (pidfd_) {
    boost::system::error_code ec;
    pidfd_->close(ec);
  }
  std::error_code fs_ec;
  std::filesystem::remove_all(workdir_, fs_ec);
  exit_status_ = r == pid_ ? status : 0;
  if (exit_fn_) {
    auto f = std::move(exit_fn_);
    f(*exit_status_);
  }
}

void EngineProcess::kill_and_reap() {
  // The owner is going away: its exit callback (which holds the owner's run, and the run holds this
  // process) will never be called, so drop it here or the two keep each other alive.
  exit_fn_ = nullptr;
  if (reaped_) return;
  ::kill(-pid_, SIGKILL);
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  std::error_code fs_ec;
  std::filesystem::remove_all(workdir_, fs_ec);
}

PythonProbe::PythonProbe(std::string python) : python_(std::move(python)) {
  const auto fail = [this](std::string why) {
    why_ = std::move(why);
    done_ = true;
  };
  if (access(python_.c_str(), X_OK) != 0) {
    fail(python_ + " is not an executable file");
    return;
  }
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) {
    fail(errno_text("pipe"));
    return;
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  std::string a0 = python_, a1 = "-I", a2 = "-S", a3 = "-c";
  std::string a4 =
      "import ast,mmap,select,signal,socket,struct,sys,tokenize,types\n"
      "sys.stdout.write('%d.%d.%d' % sys.version_info[:3])\n";
  char* argv[] = {a0.data(), a1.data(), a2.data(), a3.data(), a4.data(), nullptr};
  const int rc = posix_spawn(&pid_, python_.c_str(), &fa, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  close(out[1]);
  if (rc != 0) {
    close(out[0]);
    pid_ = -1;
    fail("cannot start " + python_ + ": " + std::strerror(rc));
    return;
  }
  fd_ = out[0];
}

PythonProbe::~PythonProbe() {
  if (fd_ >= 0) close(fd_);
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

void PythonProbe::finish() {
  done_ = true;
  std::string text;
  char buf[256];
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, 5000) <= 0) break;
    const ssize_t n = read(fd_, buf, sizeof buf);
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  close(fd_);
  fd_ = -1;
  ::kill(pid_, SIGKILL);
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  int major = 0, minor = 0;
  if (std::sscanf(text.c_str(), "%d.%d", &major, &minor) != 2) {
    why_ = python_ + " did not run the probe (a module the engine needs is missing?)";
  } else if (major < 3 || (major == 3 && minor < 8)) {
    why_ = python_ + " is Python " + text + "; the script engine needs 3.8 or newer";
  } else {
    version_ = text;
  }
}

std::optional<std::string> PythonProbe::result(std::string& why) {
  if (!done_) finish();
  why = why_;
  return version_;
}

std::optional<std::string> probe_python(const std::string& python, std::string& why) {
  PythonProbe probe(python);
  return probe.result(why);
}

}  // namespace mcemu::scripting
