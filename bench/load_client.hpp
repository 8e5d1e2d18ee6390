// Shared by the socket benchmarks (echo_ratio, slow_peers): start mcemu as a child process on
// port 0 and read its ports from the log, a closed-loop load client (one thread, epoll, N
// connections, each sending its next request when the previous reply is complete), latency
// percentiles, and a process's CPU time from /proc. Benchmarks, not tests: they print numbers.
#pragma once

#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace mcemu::bench {

using clock_type = std::chrono::steady_clock;

inline int connect_loopback(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    throw std::runtime_error("cannot connect to 127.0.0.1:" + std::to_string(port));
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

// A child process (mcemu, or this benchmark's own echo server) that is killed on destruction.
struct Child {
  pid_t pid = -1;
  std::map<std::string, std::uint16_t> ports;
  Child() = default;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    if (pid > 0) {
      ::kill(pid, SIGTERM);
      ::waitpid(pid, nullptr, 0);
    }
  }
};

// Starts mcemu on port 0 with `args`; returns once its log says "ready" (ports from "listening:").
inline void start_mcemu(Child& c, const std::string& binary, const std::vector<std::string>& args,
                        const std::string& state_dir) {
  int pipe_fd[2];
  if (::pipe(pipe_fd) != 0) throw std::runtime_error("pipe");
  c.pid = ::fork();
  if (c.pid == 0) {
    ::dup2(pipe_fd[1], 2);
    ::close(pipe_fd[0]);
    std::vector<std::string> all = {binary, "--state-dir", state_dir, "--refgo-port", "0", "--slcan-port",
                                    "0",    "--http-port", "0",       "--udp-port",   "0", "--log-level",
                                    "info"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    std::perror("execv mcemu");
    std::_Exit(127);
  }
  ::close(pipe_fd[1]);
  const std::regex listen(R"(listening: (\w+) (tcp|udp) [^ ]+:(\d+))");
  std::string pending;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(pipe_fd[0], buf, sizeof buf);
    if (n <= 0) throw std::runtime_error("mcemu exited at start-up:\n" + pending);
    pending.append(buf, static_cast<std::size_t>(n));
    std::smatch m;
    std::string::const_iterator from = pending.cbegin();
    while (std::regex_search(from, pending.cend(), m, listen)) {
      c.ports[m[1]] = static_cast<std::uint16_t>(std::stoi(m[3]));
      from = m.suffix().first;
    }
    if (pending.find(" ready") != std::string::npos) break;
  }
  // keep draining the log so that mcemu never blocks on a full pipe
  if (::fork() == 0) {
    while (::read(pipe_fd[0], buf, sizeof buf) > 0) {
    }
    std::_Exit(0);
  }
  ::close(pipe_fd[0]);
}

// CPU time (user + system) of a process so far, in seconds.
// A process's CPU time from /proc/PID/stat, in seconds: user and system separately.
struct CpuTimes {
  double user = 0, system = 0;
  double total() const { return user + system; }
};

inline CpuTimes cpu_times(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = s.rfind(')');
  std::istringstream fields(s.substr(close + 2));
  std::string f;
  unsigned long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> f; ++i) {
    if (i == 14) utime = std::stoul(f);
    if (i == 15) stime = std::stoul(f);
  }
  const auto tick = static_cast<double>(::sysconf(_SC_CLK_TCK));
  return {static_cast<double>(utime) / tick, static_cast<double>(stime) / tick};
}

inline double cpu_seconds(pid_t pid) { return cpu_times(pid).total(); }

struct Stats {
  std::uint64_t requests = 0;
  double seconds = 0;
  std::vector<double> latency_us;  // sorted
  double throughput() const { return seconds > 0 ? static_cast<double>(requests) / seconds : 0; }
  double percentile(double p) const {
    if (latency_us.empty()) return 0;
    const auto i = static_cast<std::size_t>(p * static_cast<double>(latency_us.size() - 1));
    return latency_us[i];
  }
};

using Complete = std::function<bool(const std::string&)>;

// Closed loop on `connections` connections to `port` for `duration`: each connection sends
// `request`, waits until complete(reply so far), records the latency and sends again.
inline Stats closed_loop(std::uint16_t port, const std::string& request, const Complete& complete, int connections,
                         std::chrono::milliseconds duration) {
  struct Conn {
    int fd;
    std::string buf;
    clock_type::time_point sent;
  };
  std::vector<Conn> conns;
  const int ep = ::epoll_create1(0);
  for (int i = 0; i < connections; ++i) {
    conns.push_back({connect_loopback(port), {}, {}});
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u32 = static_cast<std::uint32_t>(i);
    ::epoll_ctl(ep, EPOLL_CTL_ADD, conns.back().fd, &ev);
  }
  Stats st;
  st.latency_us.reserve(1 << 20);
  const auto send = [&](Conn& c) {
    c.sent = clock_type::now();
    if (::send(c.fd, request.data(), request.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(request.size())) {
      throw std::runtime_error("send failed");
    }
  };
  const auto start = clock_type::now();
  const auto end = start + duration;
  int open = connections;
  for (auto& c : conns) send(c);
  std::vector<epoll_event> events(static_cast<std::size_t>(connections));
  char buf[65536];
  while (open > 0) {
    const int n = ::epoll_wait(ep, events.data(), connections, 1000);
    const auto now = clock_type::now();
    for (int k = 0; k < n; ++k) {
      Conn& c = conns[events[static_cast<std::size_t>(k)].data.u32];
      const ssize_t r = ::recv(c.fd, buf, sizeof buf, 0);
      if (r <= 0) throw std::runtime_error("connection closed by the server");
      c.buf.append(buf, static_cast<std::size_t>(r));
      if (!complete(c.buf)) continue;
      c.buf.clear();
      ++st.requests;
      st.latency_us.push_back(std::chrono::duration<double, std::micro>(now - c.sent).count());
      if (now < end) {
        send(c);
      } else {
        ::epoll_ctl(ep, EPOLL_CTL_DEL, c.fd, nullptr);
        --open;
      }
    }
  }
  st.seconds = std::chrono::duration<double>(clock_type::now() - start).count();
  for (auto& c : conns) ::close(c.fd);
  ::close(ep);
  std::sort(st.latency_us.begin(), st.latency_us.end());
  return st;
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

inline std::string load_line() {
  std::ifstream in("/proc/loadavg");
  std::string s;
  std::getline(in, s);
  return s;
}

}  // namespace mcemu::bench
