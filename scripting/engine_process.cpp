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
#include <sys/uio.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "scripting/runner_embedded.hpp"
#include "scripting/sandbox.hpp"

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

// bwrap reports the end of python3 as its own exit status, 128 + n for a signal n: back to a
// wait(2) status of that signal (an os._exit(129…192) of a non-strict script reads as a signal).
int unwrap_status(int status) {
  if (WIFEXITED(status) && WEXITSTATUS(status) > 128 && WEXITSTATUS(status) < 128 + NSIG) {
    return WEXITSTATUS(status) - 128;
  }
  return status;
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

const std::string& sandboxed_bootstrap_program() {
  static const std::string k_program = exec_lock_program() + bootstrap_program();
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
  std::optional<SandboxPlan> plan;
  if (options.sandbox) {
    plan = plan_sandbox(options.bwrap, options.python, {"-I", "-S", "-u", "-c", sandboxed_bootstrap_program()}, error);
    if (!plan) return nullptr;
  }
  int sv[2] = {-1, -1};
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) {
    error = errno_text("socketpair");
    return nullptr;
  }
  auto page = SharedPage::create();
  const int runner = memfd_create("mcemu-runner", MFD_CLOEXEC);
  const int devnull = open("/dev/null", O_RDWR | O_CLOEXEC);
  int filters[2] = {-1, -1};
  std::string workdir;
  bool dir_ok = true;
  if (plan) {
    filters[0] = memfd_with(plan->process_filter);
    filters[1] = memfd_with(plan->exec_filter);
  } else {
    workdir = (std::filesystem::temp_directory_path() / "mcemu-script-XXXXXX").string();
    dir_ok = mkdtemp(workdir.data()) != nullptr;
  }
  const auto cleanup = [&] {
    for (int fd : {sv[0], sv[1], runner, devnull, filters[0], filters[1]}) {
      if (fd >= 0) close(fd);
    }
    if (dir_ok && !workdir.empty()) rmdir(workdir.c_str());
  };
  if (!page || runner < 0 || devnull < 0 || !dir_ok || (plan && (filters[0] < 0 || filters[1] < 0))) {
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

  LaunchSpec spec;
  if (plan) {
    spec.path = options.bwrap;
    spec.argv = std::move(plan->argv);
    spec.ids = plan->ids;
    spec.ignore_usr1 = true;
  } else {
    spec.path = options.python;
    spec.argv = {options.python, "-I", "-S", "-u", "-c", bootstrap_program()};
    spec.workdir = workdir;
  }
  spec.envp = {"PATH=/usr/bin:/bin", "LANG=C.UTF-8", "MALLOC_ARENA_MAX=1"};
  spec.fds = {{devnull, 0},          {devnull, 1},         {devnull, 2},
              {runner, k_fd_runner}, {sv[1], k_fd_socket}, {page->fd(), k_fd_page}};
  if (plan) spec.fds.insert(spec.fds.end(), {{filters[0], k_fd_process_filter}, {filters[1], k_fd_exec_filter}});
  spec.memory = static_cast<rlim_t>(std::max(32U, options.memory_mib)) * 1024 * 1024;
  const pid_t pid = launch(spec, error);
  if (pid < 0) {
    cleanup();
    return nullptr;
  }
  for (int fd : {sv[1], runner, devnull, filters[0], filters[1]}) {
    if (fd >= 0) close(fd);
  }
  page->close_fd();
  const int pidfd = pidfd_open(pid);
  return std::shared_ptr<EngineProcess>(
      new EngineProcess(io, pid, pidfd, sv[0], std::move(page), std::move(workdir), plan.has_value()));
}

EngineProcess::EngineProcess(asio::io_context& io, pid_t pid, int pidfd, int sock, std::unique_ptr<SharedPage> page,
                             std::string workdir, bool sandboxed)
    : io_(io),
      pid_(pid),
      socket_(io),
      page_(std::move(page)),
      workdir_(std::move(workdir)),
      sandboxed_(sandboxed),
      chunk_(k_chunk) {
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

bool EngineProcess::send_with_fd(const std::string& frame, int fd) {
  if (!socket_.is_open() || writing_ || !out_.empty()) return false;
  iovec iov{const_cast<char*>(frame.data()), frame.size()};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int))] = {};
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  cmsghdr* c = CMSG_FIRSTHDR(&msg);
  c->cmsg_level = SOL_SOCKET;
  c->cmsg_type = SCM_RIGHTS;
  c->cmsg_len = CMSG_LEN(sizeof(int));
  std::memcpy(CMSG_DATA(c), &fd, sizeof(int));
  const ssize_t n = ::sendmsg(socket_.native_handle(), &msg, MSG_DONTWAIT | MSG_NOSIGNAL);
  if (n == static_cast<ssize_t>(frame.size())) return true;
  if (n > 0) {  // the descriptor went with the first bytes; the rest follows as usual
    out_.append(frame, static_cast<std::size_t>(n));
    write_pending();
    return true;
  }
  return false;
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
  // Sandboxed, pid_ is bwrap's (it ignores SIGUSR1, set before its exec); python3 is in the group.
  if (!reaped_) ::kill(sandboxed_ ? -pid_ : pid_, SIGUSR1);
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
  exit_status_ = r == pid_ ? (sandboxed_ ? unwrap_status(status) : status) : 0;
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
