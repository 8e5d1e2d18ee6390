// The script sandbox, host side (docs/decisions/0007-script-sandbox.md): the two seccomp programs
// compiled with libseccomp (once per process), the bwrap command line for this host, the child's
// set-up between fork and exec shared by the engine process and the probes, and the start-up probe
// that runs python3 once inside the sandbox and checks that it holds. The decisions themselves are
// in core/sandbox_policy.hpp.
//
// Contract: everything on the event-loop thread (it forks; the death signal follows the forking
// thread). SandboxProbe is started in the background and read once, like PythonProbe.
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scripting/core/sandbox_policy.hpp"

namespace mcemu::scripting {

// Descriptor numbers inside the engine process (after 3 runner, 4 socketpair, 5 shared page).
inline constexpr int k_fd_process_filter = 6;  // stage 1: bwrap reads it and closes it
inline constexpr int k_fd_exec_filter = 7;     // stage 2: the bootstrap installs it and closes it

struct SandboxPlan {
  std::vector<std::string> argv;    // bwrap … -- python3 …
  std::string process_filter;       // stage-1 BPF program (struct sock_filter[])
  std::string exec_filter;          // stage-2 BPF program
  std::optional<sandbox::Ids> ids;  // the user to switch to before exec (mcemu is root)
};

// The plan for `python` started with `args` inside the sandbox; nullopt and `why` (a clause) when
// it cannot be made: no bwrap, or libseccomp failed.
std::optional<SandboxPlan> plan_sandbox(const std::string& bwrap, const std::string& python,
                                        std::vector<std::string> args, std::string& why);

// A memfd holding `bytes`, offset 0 (a filter program for bwrap or the bootstrap).
int memfd_with(const std::string& bytes);

// Python statements that install the stage-2 filter from fd 7 (through ctypes and prctl) and close
// every descriptor from 6 on; the process exits with status 120 if the kernel refuses the filter.
// The bootstrap of a sandboxed engine starts with them.
const std::string& exec_lock_program();

// What happens in the child between fork and exec (async-signal-safe calls only; everything is
// prepared before the fork).
struct LaunchSpec {
  std::string path;               // executed file
  std::vector<std::string> argv;  // argv[0] included
  std::vector<std::string> envp;
  // source descriptor → number in the child; every other descriptor is closed. 0, 1 and 2 must be
  // among the targets.
  std::vector<std::pair<int, int>> fds;
  std::string workdir;              // "" = stay where mcemu is
  rlim_t memory = RLIM_INFINITY;    // RLIMIT_AS
  std::optional<sandbox::Ids> ids;  // setgroups/setgid/setuid before exec
  bool ignore_usr1 = false;         // SIGUSR1 ignored (bwrap must survive the line sampling signal)
};
// Forks and execs; the child is in its own process group (set on both sides), has RLIMIT_CORE 0,
// RLIMIT_NOFILE 64, nice +10, default signal handlers and an empty signal mask, and gets SIGKILL
// when the forking thread ends. Returns the pid, or -1 with `error` set.
pid_t launch(const LaunchSpec& spec, std::string& error);

// Runs python3 once inside the sandbox at construction (a short program that installs the
// stage-2 filter, checks that fork, socket and execve are refused and prints its version) and
// judges the answer on result(), waiting at most a few seconds. The destructor kills and reaps a
// child still there.
class SandboxProbe {
 public:
  SandboxProbe(const std::string& bwrap, const std::string& python);
  ~SandboxProbe();
  SandboxProbe(const SandboxProbe&) = delete;
  SandboxProbe& operator=(const SandboxProbe&) = delete;

  const sandbox::Verdict& result();

 private:
  void finish();

  std::string bwrap_;
  pid_t pid_ = -1;
  int fd_ = -1;
  bool done_ = false;
  sandbox::Verdict verdict_;
};

// bwrap's version ("bubblewrap 0.8.0"), for the log and GET /api/v1/info; "bwrap" if unknown.
std::string bwrap_version(const std::string& bwrap);

}  // namespace mcemu::scripting
