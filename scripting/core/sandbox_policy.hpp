// The script sandbox's decisions (docs/decisions/0007-script-sandbox.md, docs/security.md): which
// system calls the two seccomp filters refuse, what the bubblewrap command line mounts and
// unshares, which user the engine runs as, and how a probe's answer is judged. PURE: the I/O shell
// (scripting/sandbox.cpp) compiles the rules with libseccomp, looks at the host and starts bwrap.
//
// Two filters, because bwrap installs its filter right before it executes python3 — a filter that
// refused execve would refuse that exec too:
//   stage 1 (bwrap --seccomp): everything a script never needs (process creation, ptrace, mounts,
//           new sockets, kernel interfaces…); execve stays allowed so that python3 can start;
//   stage 2 (the runner's bootstrap, before it reads the runner or any script): execve/execveat.
// A refused call fails with an errno (EPERM, or ENOSYS for clone3 so that glibc falls back to
// clone, whose flags the filter can see), never with a kill: the script gets an OSError it can print.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::scripting::sandbox {

enum class When : std::uint8_t {
  always,
  clone_without_thread,  // clone(flags) with CLONE_THREAD clear: a new process, not a thread
  clone_namespace,       // clone(flags) with any CLONE_NEW* flag
  ioctl_request,         // ioctl(fd, request) with request == arg
};

struct SyscallRule {
  std::string_view name;  // as libseccomp names it; a name unknown on this architecture is skipped
  int error;              // the errno the call fails with
  When when = When::always;
  std::uint64_t arg = 0;
};

std::span<const SyscallRule> process_rules();  // stage 1
std::span<const SyscallRule> exec_rules();     // stage 2

// A top-level entry of the host's root that the interpreter may need (/bin, /lib, /lib64, …):
// with merged /usr these are symlinks into /usr and are recreated as such; a real directory is
// mounted read-only.
struct TopLevel {
  enum class Kind : std::uint8_t { absent, symlink, directory };
  std::string path;  // "/lib64"
  Kind kind = Kind::absent;
  std::string target;  // the symlink's text ("usr/lib64")
};
// The top-level names worth looking at (the I/O part lstat()s each).
std::span<const std::string_view> top_level_names();

struct LaunchInputs {
  std::string bwrap = "/usr/bin/bwrap";
  std::string python;       // the interpreter as configured
  std::string python_real;  // its realpath(): decides whether a second prefix is needed
  std::vector<TopLevel> top;
  std::uint64_t tmp_bytes = 0;    // size of the private /tmp
  int seccomp_fd = -1;            // the stage-1 program (bwrap reads and closes it)
  std::vector<std::string> args;  // python3's arguments after argv[0]
};

inline constexpr std::uint64_t k_tmp_bytes = 16U << 20;  // the script's writable /tmp
inline constexpr std::uint32_t k_nobody = 65534;         // uid and gid when mcemu runs as root

// The complete argv of bwrap: new user (no further user namespaces), PID, IPC, network, UTS and
// cgroup namespaces; /usr and the top-level links read-only; a private size-limited /tmp as the
// working directory; the rest of the root read-only and empty (no /etc, /home, /proc, /dev, /run);
// killed when its parent dies; python3 as PID 1 (no reaper: the script cannot fork).
std::vector<std::string> bwrap_argv(const LaunchInputs& in);

// The directory to mount read-only besides /usr when the interpreter lives elsewhere (the prefix
// above its bin/ directory, e.g. /opt/python3.12 for /opt/python3.12/bin/python3.12); nullopt
// under /usr. A path that is not absolute yields nullopt too (the probe then fails visibly).
std::optional<std::string> interpreter_prefix(std::string_view python_real);

// The user the engine process switches to before it executes bwrap: nobody when mcemu runs as
// root (euid 0), else nullopt (it keeps mcemu's own, unprivileged user).
struct Ids {
  std::uint32_t uid = 0;
  std::uint32_t gid = 0;
  bool operator==(const Ids&) const = default;
};
std::optional<Ids> run_as(std::uint32_t euid);

// ---- the start-up probe (scripting/sandbox.cpp runs python3 inside the sandbox once)

// What the probe program prints on stdout, one line: "mcemu-probe ok 3.11.2", or
// "mcemu-probe fail <what>" for a check that did not hold (the filter let a fork through…).
inline constexpr std::string_view k_probe_tag = "mcemu-probe ";

struct Verdict {
  bool ok = false;
  std::string version;  // "3.11.2" when ok
  std::string reason;   // one sentence when not ok
};
// Judges the probe from its wait status (wait(2) form), stdout and stderr (bwrap's own errors
// start with "bwrap: "). `bwrap` names the program in the sentence.
Verdict judge_probe(int wait_status, std::string_view out, std::string_view err, std::string_view bwrap);

// The one sentence used by the log, GET /api/v1/info, the Code page and the UDP `code:` line when
// scripts do not start because the sandbox cannot be set up.
std::string unavailable_sentence(std::string_view reason);
// The same for the fallback that --unsafe-scripts allows.
std::string unsafe_sentence(std::string_view reason);

}  // namespace mcemu::scripting::sandbox
