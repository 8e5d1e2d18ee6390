// scripting/core/sandbox_policy: the filters' rules, the bwrap command line, the user, the probe's
// verdict and the sentences (docs/decisions/0007-script-sandbox.md).
#include "scripting/core/sandbox_policy.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cerrno>
#include <set>

namespace mcemu::scripting::sandbox {
namespace {

std::set<std::string> names(std::span<const SyscallRule> rules) {
  std::set<std::string> out;
  for (const auto& r : rules) out.emplace(r.name);
  return out;
}

const SyscallRule* find(std::span<const SyscallRule> rules, std::string_view name, When when) {
  const auto it =
      std::find_if(rules.begin(), rules.end(), [&](const auto& r) { return r.name == name && r.when == when; });
  return it == rules.end() ? nullptr : &*it;
}

TEST(SandboxRules, TheProcessFilterRefusesWhatTheIssueNames) {
  const auto n = names(process_rules());
  for (const char* call : {"fork",
                           "vfork",
                           "clone",
                           "clone3",
                           "ptrace",
                           "mount",
                           "umount2",
                           "pivot_root",
                           "socket",
                           "socketpair",
                           "connect",
                           "bind",
                           "listen",
                           "kexec_load",
                           "bpf",
                           "keyctl",
                           "unshare",
                           "setns",
                           "io_uring_setup",
                           "userfaultfd",
                           "perf_event_open",
                           "process_vm_writev",
                           "memfd_create"}) {
    EXPECT_TRUE(n.count(call)) << call;
  }
  // what the runner needs stays open: its inherited descriptors, signals within its namespace, and
  // the prctl/seccomp of the bootstrap's second filter; execve is the second filter's
  for (const char* call : {"execve", "execveat", "read", "write", "sendmsg", "recvmsg", "sendto", "recvfrom", "accept4",
                           "getsockopt", "select", "pselect6", "kill", "prctl", "seccomp", "mmap"}) {
    EXPECT_FALSE(n.count(call)) << call;
  }
}

TEST(SandboxRules, CloneIsRefusedForProcessesAndNamespacesButNotForThreads) {
  const auto* p = find(process_rules(), "clone", When::clone_without_thread);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->error, EPERM);
  std::uint64_t flags = 0;
  for (const auto& r : process_rules()) {
    if (r.name == "clone" && r.when == When::clone_namespace) flags |= r.arg;
  }
  EXPECT_EQ(flags, std::uint64_t{CLONE_NEWNS | CLONE_NEWCGROUP | CLONE_NEWUTS | CLONE_NEWIPC | CLONE_NEWUSER |
                                 CLONE_NEWPID | CLONE_NEWNET});
  EXPECT_EQ(flags & CLONE_THREAD, 0U);
  // clone3 hides its flags from the filter: ENOSYS sends glibc back to clone
  const auto* c3 = find(process_rules(), "clone3", When::always);
  ASSERT_NE(c3, nullptr);
  EXPECT_EQ(c3->error, ENOSYS);
}

TEST(SandboxRules, EveryRefusalIsAnErrnoAndTerminalInjectionIsRefused) {
  for (const auto& r : process_rules()) EXPECT_GT(r.error, 0) << r.name;
  EXPECT_NE(find(process_rules(), "ioctl", When::ioctl_request), nullptr);
  bool tiocsti = false;
  for (const auto& r : process_rules()) tiocsti |= r.name == "ioctl" && r.arg == TIOCSTI;
  EXPECT_TRUE(tiocsti);
  EXPECT_EQ(names(exec_rules()), (std::set<std::string>{"execve", "execveat"}));
}

LaunchInputs inputs() {
  LaunchInputs in;
  in.python = "/usr/bin/python3";
  in.python_real = "/usr/bin/python3.11";
  in.top = {{"/bin", TopLevel::Kind::symlink, "usr/bin"},
            {"/lib", TopLevel::Kind::directory, ""},
            {"/lib32", TopLevel::Kind::absent, ""}};
  in.tmp_bytes = k_tmp_bytes;
  in.seccomp_fd = 6;
  in.args = {"-I", "-S", "-c", "print(1)"};
  return in;
}

// the value after `flag` (the first occurrence), or "" if absent
std::string after(const std::vector<std::string>& a, const std::string& flag, std::size_t k = 1) {
  const auto it = std::find(a.begin(), a.end(), flag);
  return it == a.end() || static_cast<std::size_t>(a.end() - it) <= k ? std::string() : *(it + static_cast<long>(k));
}

TEST(BwrapArgv, NamespacesMountsAndTheCommand) {
  const auto a = bwrap_argv(inputs());
  ASSERT_GE(a.size(), 10U);
  EXPECT_EQ(a.front(), "/usr/bin/bwrap");
  for (const char* flag : {"--unshare-all", "--unshare-user", "--disable-userns", "--die-with-parent", "--as-pid-1"}) {
    EXPECT_NE(std::find(a.begin(), a.end(), flag), a.end()) << flag;
  }
  for (const char* absent : {"--share-net", "--proc", "--dev", "--bind", "--new-session"}) {
    EXPECT_EQ(std::find(a.begin(), a.end(), absent), a.end()) << absent << " must not be there";
  }
  EXPECT_EQ(after(a, "--ro-bind"), "/usr");
  EXPECT_EQ(after(a, "--symlink"), "usr/bin");
  EXPECT_EQ(after(a, "--symlink", 2), "/bin");
  EXPECT_EQ(after(a, "--size"), std::to_string(16U << 20));
  EXPECT_EQ(after(a, "--size", 2), "--tmpfs");  // --size applies to the --tmpfs right after it
  EXPECT_EQ(after(a, "--size", 3), "/tmp");
  EXPECT_EQ(after(a, "--remount-ro"), "/");
  EXPECT_EQ(after(a, "--chdir"), "/tmp");
  EXPECT_EQ(after(a, "--seccomp"), "6");
  // /lib is a real directory here: mounted read-only; /lib32 is absent: nothing
  const auto lib = std::find(a.begin(), a.end(), "/lib");
  ASSERT_NE(lib, a.end());
  EXPECT_EQ(*(lib - 1), "--ro-bind");
  EXPECT_EQ(std::find(a.begin(), a.end(), "/lib32"), a.end());
  // the command last, after "--"
  const auto dd = std::find(a.begin(), a.end(), "--");
  ASSERT_NE(dd, a.end());
  EXPECT_EQ(std::vector<std::string>(dd + 1, a.end()),
            (std::vector<std::string>{"/usr/bin/python3", "-I", "-S", "-c", "print(1)"}));
  // the read-only remount comes after every mount (bwrap applies them in order)
  EXPECT_GT(std::find(a.begin(), a.end(), "--remount-ro") - a.begin(),
            std::find(a.begin(), a.end(), "--tmpfs") - a.begin());
}

TEST(BwrapArgv, AnInterpreterOutsideUsrGetsItsPrefixReadOnly) {
  auto in = inputs();
  in.python = in.python_real = "/opt/py312/bin/python3.12";
  const auto a = bwrap_argv(in);
  const auto it = std::find(a.begin(), a.end(), "/opt/py312");
  ASSERT_NE(it, a.end());
  EXPECT_EQ(*(it - 1), "--ro-bind");
  EXPECT_EQ(*(it + 1), "/opt/py312");
}

TEST(InterpreterPrefix, Table) {
  struct Case {
    const char* real;
    std::optional<std::string> prefix;
  };
  for (const auto& c : {Case{"/usr/bin/python3.11", std::nullopt}, Case{"/usr/local/bin/python3", std::nullopt},
                        Case{"/opt/py/bin/python3", "/opt/py"},
                        Case{"/root/.pyenv/versions/3.12.1/bin/python3.12", "/root/.pyenv/versions/3.12.1"},
                        Case{"/srv/python3", "/srv"}, Case{"/python3", std::nullopt}, Case{"", std::nullopt},
                        Case{"relative/bin/python3", std::nullopt}}) {
    EXPECT_EQ(interpreter_prefix(c.real), c.prefix) << c.real;
  }
}

TEST(RunAs, NobodyOnlyForRoot) {
  EXPECT_EQ(run_as(0), (Ids{65534, 65534}));
  EXPECT_FALSE(run_as(1000));
  EXPECT_FALSE(run_as(10001));
}

constexpr int exited(int code) { return code << 8; }

TEST(JudgeProbe, Table) {
  struct Case {
    int status;
    std::string out;
    bool ok;
    std::string in_reason;
  };
  const Case cases[] = {
      {exited(0), "mcemu-probe ok 3.11.2\n", true, ""},
      {exited(0), "noise\nmcemu-probe ok 3.12.0\n", true, ""},
      {exited(1), "mcemu-probe ok 3.11.2\n", false, "exited with status 1"},
      {exited(0), "mcemu-probe fail fork was allowed\n", false, "a check inside it did not hold: fork was allowed"},
      {exited(1),
       "bwrap: No permissions to creating new namespace, likely because the kernel does not allow non-privileged user "
       "namespaces.\n",
       false, "user namespaces are disabled or blocked"},
      {exited(1), "bwrap: Can't mount tmpfs on /newroot: Operation not permitted\n", false, "/usr/bin/bwrap refused"},
      {exited(120), "mcemu-seccomp: prctl refused the exec filter\n", false, "the kernel refused the seccomp filter"},
      {9, "", false, "was killed by signal 9"},
      {exited(0), "", false, "exited with status 0"},
  };
  for (const auto& c : cases) {
    const Verdict v = judge_probe(c.status, c.out, c.out, "/usr/bin/bwrap");
    EXPECT_EQ(v.ok, c.ok) << c.out;
    if (c.ok) {
      EXPECT_FALSE(v.version.empty());
      EXPECT_TRUE(v.reason.empty());
    } else {
      EXPECT_NE(v.reason.find(c.in_reason), std::string::npos) << v.reason;
      EXPECT_EQ(v.reason.find('\n'), std::string::npos) << "one line: " << v.reason;
    }
  }
  EXPECT_EQ(judge_probe(exited(0), "mcemu-probe ok 3.11.2\n", "", "b").version, "3.11.2");
}

TEST(Sentences, NameTheFlagAndTheReasonOnOneLine) {
  const auto u = unavailable_sentence("bwrap refused: x");
  EXPECT_NE(u.find("--unsafe-scripts"), std::string::npos);
  EXPECT_NE(u.find("bwrap refused: x"), std::string::npos);
  EXPECT_EQ(u.find('\n'), std::string::npos);
  const auto s = unsafe_sentence("bwrap refused: x");
  EXPECT_EQ(s.rfind("UNSAFE", 0), 0U);
  EXPECT_NE(s.find("bwrap refused: x"), std::string::npos);
}

}  // namespace
}  // namespace mcemu::scripting::sandbox
