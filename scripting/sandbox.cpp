#include "scripting/sandbox.hpp"

#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <sched.h>
#include <seccomp.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

namespace mcemu::scripting {

namespace {

using sandbox::SyscallRule;
using sandbox::When;

constexpr auto k_probe_wait_ms = 5000;

std::string errno_text(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

// One argument comparison of a rule; libseccomp's SCMP_A0… macros are C compound literals, which
// clang's -Wpedantic refuses in C++.
scmp_arg_cmp arg_cmp(unsigned int arg, scmp_compare op, scmp_datum_t a, scmp_datum_t b) {
  scmp_arg_cmp c{};
  c.arg = arg;
  c.op = op;
  c.datum_a = a;
  c.datum_b = b;
  return c;
}

// One filter, default allow, with `rules` → ERRNO; the BPF program as bytes. Empty with `why` on
// failure. A name the architecture does not have is skipped (fork on aarch64…).
std::string compile(std::span<const SyscallRule> rules, std::string& why) {
  scmp_filter_ctx ctx = seccomp_init(SCMP_ACT_ALLOW);
  if (!ctx) {
    why = "libseccomp cannot make a filter";
    return {};
  }
  int rc = 0;
  for (const auto& r : rules) {
    const std::string name(r.name);
    const int nr = seccomp_syscall_resolve_name(name.c_str());
    if (nr == __NR_SCMP_ERROR) continue;
    const std::uint32_t action = SCMP_ACT_ERRNO(static_cast<std::uint32_t>(r.error));
    switch (r.when) {
      case When::always: rc = seccomp_rule_add(ctx, action, nr, 0); break;
      case When::clone_without_thread:
        rc = seccomp_rule_add(ctx, action, nr, 1, arg_cmp(0, SCMP_CMP_MASKED_EQ, CLONE_THREAD, 0));
        break;
      case When::clone_namespace:
        rc = seccomp_rule_add(ctx, action, nr, 1, arg_cmp(0, SCMP_CMP_MASKED_EQ, r.arg, r.arg));
        break;
      case When::ioctl_request:
        rc = seccomp_rule_add(ctx, action, nr, 1, arg_cmp(1, SCMP_CMP_MASKED_EQ, 0xFFFFFFFFU, r.arg));
        break;
    }
    // -EOPNOTSUPP/-EDOM: a pseudo syscall of another architecture; anything else is a real failure
    if (rc != 0 && rc != -EOPNOTSUPP && rc != -EDOM) {
      why = "libseccomp refused the rule for " + name + ": " + std::strerror(-rc);
      seccomp_release(ctx);
      return {};
    }
  }
  std::string out;
  const int fd = memfd_create("mcemu-bpf", MFD_CLOEXEC);
  if (fd < 0) {
    why = errno_text("memfd_create");
  } else if ((rc = seccomp_export_bpf(ctx, fd)) != 0) {
    why = std::string("libseccomp cannot export the filter: ") + std::strerror(-rc);
  } else {
    struct stat st {};
    fstat(fd, &st);
    out.resize(static_cast<std::size_t>(st.st_size));
    if (pread(fd, out.data(), out.size(), 0) != static_cast<ssize_t>(out.size())) {
      why = errno_text("reading the filter");
      out.clear();
    }
  }
  if (fd >= 0) close(fd);
  seccomp_release(ctx);
  return out;
}

struct Filters {
  std::string process, exec, why;
};

const Filters& filters() {
  static const Filters k_filters = [] {
    Filters f;
    f.process = compile(sandbox::process_rules(), f.why);
    if (!f.process.empty()) f.exec = compile(sandbox::exec_rules(), f.why);
    return f;
  }();
  return k_filters;
}

std::vector<sandbox::TopLevel> host_top_levels() {
  std::vector<sandbox::TopLevel> out;
  for (const auto name : sandbox::top_level_names()) {
    sandbox::TopLevel t;
    t.path = std::string(name);
    struct stat st {};
    if (lstat(t.path.c_str(), &st) == 0) {
      if (S_ISLNK(st.st_mode)) {
        std::array<char, PATH_MAX> buf{};
        const ssize_t n = readlink(t.path.c_str(), buf.data(), buf.size() - 1);
        if (n > 0) {
          t.kind = sandbox::TopLevel::Kind::symlink;
          t.target.assign(buf.data(), static_cast<std::size_t>(n));
        }
      } else if (S_ISDIR(st.st_mode)) {
        t.kind = sandbox::TopLevel::Kind::directory;
      }
    }
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// Everything the child does between fork and exec: async-signal-safe calls only.
[[noreturn]] void child(pid_t parent, const char* path, char* const argv[], char* const envp[],
                        const std::pair<int, int>* fds, std::size_t nfds, const char* workdir, rlim_t memory,
                        const sandbox::Ids* ids, bool ignore_usr1) {
  setpgid(0, 0);
  sigset_t none;
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, nullptr);
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  for (int s = 1; s < NSIG; ++s) sigaction(s, &dfl, nullptr);  // SIGPIPE was ignored by mcemu
  if (ignore_usr1) {
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigaction(SIGUSR1, &ign, nullptr);  // inherited through bwrap; the runner installs its handler
  }
  const rlimit as{memory, memory};
  setrlimit(RLIMIT_AS, &as);
  const rlimit core{0, 0};
  setrlimit(RLIMIT_CORE, &core);
  setpriority(PRIO_PROCESS, 0, 10);
  // Move the sources above every target first, so that no dup2 overwrites another source (before
  // RLIMIT_NOFILE 64: with a thousand clients mcemu's descriptors reach far beyond 64).
  std::array<int, 16> moved{};
  for (std::size_t k = 0; k < nfds; ++k) {
    moved[k] = fcntl(fds[k].first, F_DUPFD, 16);
    if (moved[k] < 0) _exit(126);
  }
  int top = 0;
  for (std::size_t k = 0; k < nfds; ++k) {
    if (dup2(moved[k], fds[k].second) < 0) _exit(126);
    top = std::max(top, fds[k].second);
  }
  if (syscall(SYS_close_range, static_cast<unsigned>(top + 1), ~0U, 0U) != 0) {
    for (int fd = top + 1; fd < 4096; ++fd) close(fd);
  }
  const rlimit files{64, 64};
  setrlimit(RLIMIT_NOFILE, &files);
  if (workdir[0] != '\0' && chdir(workdir) != 0) _exit(126);
  if (ids) {
    if (setgroups(0, nullptr) != 0 || setgid(ids->gid) != 0 || setuid(ids->uid) != 0) _exit(126);
  }
  // After the change of user: a credential change clears the death signal.
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(125);  // mcemu died before the death signal was armed
  execve(path, argv, envp);
  _exit(127);
}

const std::string& probe_program() {
  static const std::string k_program =
      exec_lock_program() +
      "import ast,mmap,select,signal,socket,struct,sys,tokenize,types\n"
      "def fail(what):\n"
      " sys.stdout.write('mcemu-probe fail '+what+'\\n');sys.stdout.flush();os._exit(0)\n"
      "def refused(f):\n"
      " try:f()\n"
      " except OSError:return True\n"
      " return False\n"
      "def fork():\n"
      " if os.fork()==0:os._exit(0)\n"
      "if not refused(fork):fail('fork was allowed')\n"
      "if not refused(lambda:socket.socket(socket.AF_INET,socket.SOCK_STREAM)):fail('a socket could be made')\n"
      "if os.path.exists('/etc') or os.path.exists('/proc'):fail('/etc or /proc is visible')\n"
      "if not refused(lambda:os.execv(sys.executable,[sys.executable,'-I','-S','-c',"
      "'import sys;sys.stdout.write(\"mcemu-probe fail execve was allowed\\\\n\")'])):fail('execve was allowed')\n"
      "sys.stdout.write('mcemu-probe ok %d.%d.%d\\n'%sys.version_info[:3])\n";
  return k_program;
}

}  // namespace

int memfd_with(const std::string& bytes) {
  const int fd = memfd_create("mcemu-filter", MFD_CLOEXEC);
  if (fd < 0) return -1;
  if (write(fd, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size()) || lseek(fd, 0, SEEK_SET) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

const std::string& exec_lock_program() {
  static const std::string k_program =
      "import os\n"
      "def _mcemu_lock():\n"
      " import ctypes\n"
      " b=os.pread(7,os.fstat(7).st_size,0);os.close(7)\n"
      " f=ctypes.create_string_buffer(b,len(b))\n"
      " class P(ctypes.Structure):_fields_=[('n',ctypes.c_ushort),('f',ctypes.c_void_p)]\n"
      " p=P(len(b)//8,ctypes.addressof(f))\n"
      " c=ctypes.CDLL(None,use_errno=True)\n"
      " c.prctl.argtypes=[ctypes.c_int,ctypes.c_ulong,ctypes.c_void_p,ctypes.c_ulong,ctypes.c_ulong]\n"
      " if c.prctl(22,2,ctypes.byref(p),0,0)!=0:os.write(2,b'mcemu-seccomp: prctl refused the exec filter\\n');"
      "os._exit(120)\n"  // PR_SET_SECCOMP, SECCOMP_MODE_FILTER
      "_mcemu_lock();del _mcemu_lock\n"
      "os.closerange(6,64)\n";
  return k_program;
}

std::optional<SandboxPlan> plan_sandbox(const std::string& bwrap, const std::string& python,
                                        std::vector<std::string> args, std::string& why) {
  if (access(bwrap.c_str(), X_OK) != 0) {
    why = bwrap + " is missing (the Debian package bubblewrap)";
    return std::nullopt;
  }
  const Filters& f = filters();
  if (f.process.empty() || f.exec.empty()) {
    why = f.why;
    return std::nullopt;
  }
  sandbox::LaunchInputs in;
  in.bwrap = bwrap;
  in.python = python;
  if (char* real = realpath(python.c_str(), nullptr)) {
    in.python_real = real;
    std::free(real);
  }
  in.top = host_top_levels();
  in.tmp_bytes = sandbox::k_tmp_bytes;
  in.seccomp_fd = k_fd_process_filter;
  in.args = std::move(args);
  SandboxPlan plan;
  plan.argv = sandbox::bwrap_argv(in);
  plan.process_filter = f.process;
  plan.exec_filter = f.exec;
  plan.ids = sandbox::run_as(static_cast<std::uint32_t>(geteuid()));
  return plan;
}

pid_t launch(const LaunchSpec& spec, std::string& error) {
  if (spec.fds.size() > 16) {
    error = "too many descriptors for the child";
    return -1;
  }
  // Everything the child needs is prepared before fork (no allocation after it).
  std::vector<std::string> argv_s = spec.argv, envp_s = spec.envp;
  auto argv = pointers(argv_s);
  auto envp = pointers(envp_s);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    error = errno_text("fork");
    return -1;
  }
  if (pid == 0) {
    child(parent, spec.path.c_str(), argv.data(), envp.data(), spec.fds.data(), spec.fds.size(), spec.workdir.c_str(),
          spec.memory, spec.ids ? &*spec.ids : nullptr, spec.ignore_usr1);
  }
  setpgid(pid, pid);  // also here, so that signals reach the group however the race goes
  return pid;
}

SandboxProbe::SandboxProbe(const std::string& bwrap, const std::string& python) : bwrap_(bwrap) {
  const auto fail = [this](std::string why) {
    verdict_.reason = std::move(why);
    done_ = true;
  };
  std::string why;
  auto plan = plan_sandbox(bwrap, python, {"-I", "-S", "-c", probe_program()}, why);
  if (!plan) {
    fail(why);
    return;
  }
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) {
    fail(errno_text("pipe"));
    return;
  }
  const int devnull = open("/dev/null", O_RDONLY | O_CLOEXEC);
  const int f1 = memfd_with(plan->process_filter);
  const int f2 = memfd_with(plan->exec_filter);
  LaunchSpec spec;
  spec.path = bwrap;
  spec.argv = plan->argv;
  spec.envp = {"PATH=/usr/bin:/bin", "LANG=C.UTF-8"};
  spec.fds = {{devnull, 0}, {out[1], 1}, {out[1], 2}, {f1, k_fd_process_filter}, {f2, k_fd_exec_filter}};
  spec.memory = 256ULL << 20;
  spec.ids = plan->ids;
  if (devnull >= 0 && f1 >= 0 && f2 >= 0) pid_ = launch(spec, why);
  for (int fd : {devnull, f1, f2, out[1]}) {
    if (fd >= 0) close(fd);
  }
  if (pid_ < 0) {
    close(out[0]);
    fail(why.empty() ? errno_text("sandbox probe set-up") : why);
    return;
  }
  fd_ = out[0];
}

SandboxProbe::~SandboxProbe() {
  if (fd_ >= 0) close(fd_);
  if (pid_ > 0) {
    ::kill(-pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

void SandboxProbe::finish() {
  done_ = true;
  std::string text;
  char buf[512];
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, k_probe_wait_ms) <= 0) break;
    const ssize_t n = read(fd_, buf, sizeof buf);
    if (n <= 0) break;
    if (text.size() < 16384) text.append(buf, static_cast<std::size_t>(n));
  }
  close(fd_);
  fd_ = -1;
  int status = 0;
  // normally it has ended by now (its output is complete); a hung probe is killed
  if (waitpid(pid_, &status, WNOHANG) == 0) {
    ::kill(-pid_, SIGKILL);
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  pid_ = -1;
  verdict_ = sandbox::judge_probe(status, text, text, bwrap_);
}

const sandbox::Verdict& SandboxProbe::result() {
  if (!done_) finish();
  return verdict_;
}

std::string bwrap_version(const std::string& bwrap) {
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) return "bwrap";
  const int devnull = open("/dev/null", O_RDONLY | O_CLOEXEC);
  LaunchSpec spec;
  spec.path = bwrap;
  spec.argv = {bwrap, "--version"};
  spec.fds = {{devnull, 0}, {out[1], 1}, {devnull, 2}};
  std::string why;
  const pid_t pid = devnull >= 0 ? launch(spec, why) : -1;
  close(out[1]);
  if (devnull >= 0) close(devnull);
  std::string text;
  char buf[128];
  for (;;) {
    pollfd p{out[0], POLLIN, 0};
    if (pid < 0 || poll(&p, 1, k_probe_wait_ms) <= 0) break;
    const ssize_t n = read(out[0], buf, sizeof buf);
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  close(out[0]);
  if (pid > 0) {
    int status = 0;
    ::kill(-pid, SIGKILL);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text.empty() ? std::string("bwrap") : text;
}

}  // namespace mcemu::scripting
