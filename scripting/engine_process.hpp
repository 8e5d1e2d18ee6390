// One script engine process (scripting.md §10.2): Debian's python3 started as `-I -S -u` with the
// embedded runner, in its own process group, with RLIMIT_AS / RLIMIT_CORE 0 / RLIMIT_NOFILE 64,
// nice +10, PR_SET_PDEATHSIG SIGKILL, stdin/stdout/stderr /dev/null; fd 3 = the runner (memfd),
// fd 4 = its end of the socketpair, fd 5 = the shared page. Sandboxed (the default, sandbox.hpp):
// started through bwrap as nobody (when mcemu is root), fd 6/7 = the two seccomp programs, the
// working directory the sandbox's private /tmp. Unsandboxed (--unsafe-scripts fallback): an empty
// temporary working directory of mcemu's. The loop's end of the socketpair is a non-blocking Asio
// peer; the exit is seen on a pidfd.
//
// Contract: created, used and destroyed on the event-loop thread, which is also the thread that
// forks (the death signal follows the forking thread). Signals go to the whole process group
// while the leader has not been reaped (its zombie keeps the group id reserved). Callbacks run
// from io_context handlers; the object stays alive (shared_ptr) until the process is reaped.
#pragma once

#include <sys/types.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scripting/core/ipc.hpp"
#include "scripting/shared_page.hpp"

namespace mcemu::scripting {

struct SpawnOptions {
  std::string python = "/usr/bin/python3";
  unsigned memory_mib = 256;  // RLIMIT_AS; values below 32 are taken as 32
  bool sandbox = true;        // through bwrap with the seccomp filters (sandbox.hpp)
  std::string bwrap = "/usr/bin/bwrap";
};

// The `-c` program that loads the runner modules from fd 3 and runs the last one's main(); the
// sandboxed one first installs the stage-2 filter (exec_lock_program()).
const std::string& bootstrap_program();
const std::string& sandboxed_bootstrap_program();
// The runner modules in the container format fd 3 holds: per module u16 name length, name,
// u32 source length, source.
const std::string& runner_container();

class EngineProcess : public std::enable_shared_from_this<EngineProcess> {
 public:
  // Starts a process; nullptr with `error` set when that fails (no fork, no socketpair…).
  static std::shared_ptr<EngineProcess> spawn(boost::asio::io_context& io, const SpawnOptions& options,
                                              std::string& error);
  ~EngineProcess();
  EngineProcess(const EngineProcess&) = delete;
  EngineProcess& operator=(const EngineProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool sandboxed() const { return sandboxed_; }
  SharedPage& page() { return *page_; }

  // ---- the channel
  // The next complete message already received, if any; `error` on a framing error.
  std::optional<ipc::Message> next(bool& error);
  // Calls `on_data` (once) when more bytes have arrived or the peer closed (then closed() is true).
  void read_more(std::function<void()> on_data);
  bool closed() const { return eof_; }
  // Reads, without blocking, whatever the process has already written (used when it ends).
  void read_available();
  // Sends a frame: at once if the socket takes it, else queued and written asynchronously.
  void send(std::string frame);
  // Sends a frame with descriptor `fd` attached (SCM_RIGHTS; the process gets its own copy, the
  // caller keeps and closes `fd`). Only when nothing else is queued and the socket takes it at once;
  // false otherwise (nothing was sent).
  bool send_with_fd(const std::string& frame, int fd);
  void close_channel();

  // ---- signals to the process group (no effect once reaped)
  void kill_group();
  void stop_group();
  void continue_group();
  void sample_line();  // SIGUSR1 to the runner only (sandboxed: to the group; bwrap ignores it)

  // Called once with the wait status (waitid si_code/si_status folded into a wait(2)-style int).
  void on_exit(std::function<void(int wait_status)> fn);
  bool reaped() const { return reaped_; }
  // Blocking: SIGKILL and reap now (engine destruction, when the loop may not run again).
  void kill_and_reap();

 private:
  EngineProcess(boost::asio::io_context& io, pid_t pid, int pidfd, int sock, std::unique_ptr<SharedPage> page,
                std::string workdir, bool sandboxed);
  void watch_exit();
  void reap();
  void write_pending();
  void signal_group(int sig);

  boost::asio::io_context& io_;
  pid_t pid_;
  boost::asio::local::stream_protocol::socket socket_;
  std::optional<boost::asio::posix::stream_descriptor> pidfd_;
  std::unique_ptr<SharedPage> page_;
  std::string workdir_;  // "" when sandboxed (its /tmp is the sandbox's own)
  bool sandboxed_ = false;
  std::string in_;
  std::vector<char> chunk_;
  std::string out_;
  bool writing_ = false;
  bool reading_ = false;
  bool eof_ = false;
  bool reaped_ = false;
  std::function<void(int)> exit_fn_;
  std::optional<int> exit_status_;
};

// The availability check of scripting.md §10.1.8 without making start-up wait for it: the
// constructor starts `python -I -S -c …` (it imports the modules the runner needs and prints its
// version) and returns at once; result() reads the answer the first time it is asked, waiting at
// most a few seconds if the child has not finished yet (normally it has: it runs beside the rest
// of the start-up). The destructor kills and reaps a child that is still there.
class PythonProbe {
 public:
  explicit PythonProbe(std::string python);
  ~PythonProbe();
  PythonProbe(const PythonProbe&) = delete;
  PythonProbe& operator=(const PythonProbe&) = delete;

  // The version ("3.11.2") if the interpreter runs and is ≥ 3.8; else nullopt and `why`.
  std::optional<std::string> result(std::string& why);

 private:
  void finish();

  std::string python_;
  pid_t pid_ = -1;
  int fd_ = -1;
  bool done_ = false;
  std::optional<std::string> version_;
  std::string why_;
};

// The same, blocking: starts the probe and waits for its answer.
std::optional<std::string> probe_python(const std::string& python, std::string& why);

}  // namespace mcemu::scripting
