#include "scripting/core/sandbox_policy.hpp"

#include <sched.h>
#include <sys/ioctl.h>
#include <sys/wait.h>

#include <array>
#include <cerrno>

namespace mcemu::scripting::sandbox {

namespace {

constexpr int k_eperm = EPERM;

// Stage 1. What a script never needs: the runner is one single-threaded process that talks to mcemu
// over descriptors it inherited (mcnet sockets arrive the same way, opened by mcemu).
constexpr std::array k_process_rules = std::to_array<SyscallRule>({
    // new processes: fork, vfork, clone without CLONE_THREAD, any clone with a new namespace; clone3
    // passes its flags in memory the filter cannot read, so it fails with ENOSYS and glibc falls
    // back to clone (threads keep working)
    {"fork", k_eperm},
    {"vfork", k_eperm},
    {"clone", k_eperm, When::clone_without_thread},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWNS},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWCGROUP},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWUTS},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWIPC},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWUSER},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWPID},
    {"clone", k_eperm, When::clone_namespace, CLONE_NEWNET},
    {"clone3", ENOSYS},
    {"unshare", k_eperm},
    {"setns", k_eperm},
    // other processes
    {"ptrace", k_eperm},
    {"process_vm_readv", k_eperm},
    {"process_vm_writev", k_eperm},
    {"process_madvise", k_eperm},
    {"kcmp", k_eperm},
    {"pidfd_getfd", k_eperm},
    // the file system view
    {"mount", k_eperm},
    {"umount2", k_eperm},
    {"pivot_root", k_eperm},
    {"chroot", k_eperm},
    {"open_tree", k_eperm},
    {"move_mount", k_eperm},
    {"fsopen", k_eperm},
    {"fsconfig", k_eperm},
    {"fsmount", k_eperm},
    {"fspick", k_eperm},
    {"mount_setattr", k_eperm},
    {"name_to_handle_at", k_eperm},
    {"open_by_handle_at", k_eperm},
    {"mknod", k_eperm},
    {"mknodat", k_eperm},
    // the network: no new sockets, no addresses of its own; the inherited ones keep working
    {"socket", k_eperm},
    {"socketpair", k_eperm},
    {"bind", k_eperm},
    {"listen", k_eperm},
    {"connect", k_eperm},
    // kernel interfaces
    {"bpf", k_eperm},
    {"perf_event_open", k_eperm},
    {"userfaultfd", k_eperm},
    {"io_uring_setup", k_eperm},
    {"io_uring_enter", k_eperm},
    {"io_uring_register", k_eperm},
    {"kexec_load", k_eperm},
    {"kexec_file_load", k_eperm},
    {"init_module", k_eperm},
    {"finit_module", k_eperm},
    {"delete_module", k_eperm},
    {"reboot", k_eperm},
    {"swapon", k_eperm},
    {"swapoff", k_eperm},
    {"acct", k_eperm},
    {"quotactl", k_eperm},
    {"quotactl_fd", k_eperm},
    {"syslog", k_eperm},
    {"iopl", k_eperm},
    {"ioperm", k_eperm},
    {"lookup_dcookie", k_eperm},
    {"uselib", k_eperm},
    {"vhangup", k_eperm},
    {"nfsservctl", k_eperm},
    {"_sysctl", k_eperm},
    {"sysfs", k_eperm},
    {"fanotify_init", k_eperm},
    {"personality", k_eperm},
    {"add_key", k_eperm},
    {"request_key", k_eperm},
    {"keyctl", k_eperm},
    {"settimeofday", k_eperm},
    {"clock_settime", k_eperm},
    {"clock_adjtime", k_eperm},
    {"adjtimex", k_eperm},
    // memory outside the address-space limit (RLIMIT_AS does not count memfd pages)
    {"memfd_create", k_eperm},
    {"memfd_secret", k_eperm},
    // typing into a terminal (the process has none: it is a session leader without one)
    {"ioctl", k_eperm, When::ioctl_request, TIOCSTI},
    {"ioctl", k_eperm, When::ioctl_request, TIOCLINUX},
});

constexpr std::array k_exec_rules = std::to_array<SyscallRule>({
    {"execve", k_eperm},
    {"execveat", k_eperm},
});

// /usr itself is always mounted.
constexpr std::array<std::string_view, 6> k_top_names{"/bin", "/sbin", "/lib", "/lib64", "/lib32", "/libx32"};

std::string first_line(std::string_view text) {
  const auto end = text.find('\n');
  std::string line(text.substr(0, end));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// The first line of `text` that starts with `prefix`, without the prefix; nullopt if none.
std::optional<std::string> line_after(std::string_view text, std::string_view prefix) {
  std::size_t at = 0;
  while (at < text.size()) {
    const auto end = text.find('\n', at);
    const auto line = text.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at);
    if (line.substr(0, prefix.size()) == prefix) return first_line(line.substr(prefix.size()));
    if (end == std::string_view::npos) break;
    at = end + 1;
  }
  return std::nullopt;
}

bool contains(std::string_view text, std::string_view what) { return text.find(what) != std::string_view::npos; }

}  // namespace

std::span<const SyscallRule> process_rules() { return k_process_rules; }
std::span<const SyscallRule> exec_rules() { return k_exec_rules; }

std::span<const std::string_view> top_level_names() { return k_top_names; }

std::optional<std::string> interpreter_prefix(std::string_view python_real) {
  if (python_real.empty() || python_real.front() != '/') return std::nullopt;
  if (python_real.substr(0, 5) == "/usr/") return std::nullopt;
  const auto slash = python_real.rfind('/');
  std::string_view dir = python_real.substr(0, slash);  // …/bin
  const auto up = dir.rfind('/');
  const std::string_view leaf = dir.substr(up + 1);
  // /opt/py/bin/python3 → /opt/py; a file directly in a directory not named bin → that directory
  const std::string_view prefix = leaf == "bin" && up > 0 ? dir.substr(0, up) : dir;
  if (prefix.empty()) return std::nullopt;  // an interpreter in / itself: nothing sensible to mount
  return std::string(prefix);
}

std::optional<Ids> run_as(std::uint32_t euid) {
  if (euid != 0) return std::nullopt;
  return Ids{k_nobody, k_nobody};
}

std::vector<std::string> bwrap_argv(const LaunchInputs& in) {
  std::vector<std::string> a{in.bwrap,
                             "--unshare-all",  // user, ipc, pid, net, uts, cgroup
                             "--unshare-user",
                             "--disable-userns",  // and no further user namespaces inside
                             "--die-with-parent",
                             "--as-pid-1",
                             "--ro-bind",
                             "/usr",
                             "/usr"};
  for (const auto& t : in.top) {
    if (t.kind == TopLevel::Kind::symlink) {
      a.insert(a.end(), {"--symlink", t.target, t.path});
    } else if (t.kind == TopLevel::Kind::directory) {
      a.insert(a.end(), {"--ro-bind", t.path, t.path});
    }
  }
  if (auto prefix = interpreter_prefix(in.python_real)) a.insert(a.end(), {"--ro-bind", *prefix, *prefix});
  a.insert(a.end(), {"--size", std::to_string(in.tmp_bytes), "--tmpfs", "/tmp", "--remount-ro", "/", "--chdir", "/tmp",
                     "--seccomp", std::to_string(in.seccomp_fd), "--", in.python});
  a.insert(a.end(), in.args.begin(), in.args.end());
  return a;
}

Verdict judge_probe(int wait_status, std::string_view out, std::string_view err, std::string_view bwrap) {
  Verdict v;
  if (auto ok = line_after(out, std::string(k_probe_tag) + "ok ")) {
    if (WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0 && !ok->empty()) {
      v.ok = true;
      v.version = *ok;
      return v;
    }
  }
  if (auto fail = line_after(out, std::string(k_probe_tag) + "fail ")) {
    v.reason = "a check inside it did not hold: " + *fail;
    return v;
  }
  if (auto said = line_after(err, "bwrap: ")) {
    v.reason = std::string(bwrap) + " refused: " + *said;
    if (contains(*said, "namespace") || contains(*said, "Operation not permitted") ||
        contains(*said, "Permission denied")) {
      v.reason += " — user namespaces are disabled or blocked, e.g. by a container's seccomp or AppArmor profile";
    }
    return v;
  }
  if (auto seccomp = line_after(err, "mcemu-seccomp: ")) {
    v.reason = "the kernel refused the seccomp filter: " + *seccomp;
    return v;
  }
  std::string how;
  if (WIFSIGNALED(wait_status)) {
    how = "was killed by signal " + std::to_string(WTERMSIG(wait_status));
  } else if (WIFEXITED(wait_status)) {
    how = "exited with status " + std::to_string(WEXITSTATUS(wait_status));
  } else {
    how = "did not answer";
  }
  v.reason = "the check of python3 inside " + std::string(bwrap) + " " + how;
  const std::string said = first_line(err);
  if (!said.empty()) v.reason += ": " + said;
  return v;
}

std::string unavailable_sentence(std::string_view reason) {
  return "scripts do not run because the script sandbox cannot be set up (" + std::string(reason) +
         "); start mcemu with --unsafe-scripts to run them without it, see docs/security.md";
}

std::string unsafe_sentence(std::string_view reason) {
  return "UNSAFE: scripts run without the script sandbox, with mcemu's user rights and network access "
         "(--unsafe-scripts; the sandbox cannot be set up: " +
         std::string(reason) + ")";
}

}  // namespace mcemu::scripting::sandbox
