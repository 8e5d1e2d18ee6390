// Benchmarks of the script engine (scripting.md §10.1.2, §10.1.5), reported, never asserted:
//   A. mcdrive round trips per second from a tight script loop (mc.ReadStatusword()),
//   B. the same number of synchronous round trips between python3 and a minimal Boost.Asio peer
//      over a socketpair (same frame sizes), as the reference of §10.1.5,
//   C. stop latency: stop() of a spinning script until its process is reaped,
//   D. start latency: start() until the script's first print, with the 100 ms of drive time before
//      `compile` stepped at once (what is left is the process start, the runner's boot and compile).
// A and B alternate; medians of the rounds are printed. Usage: scripting_bench [rounds] [calls].
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "scripting/engine.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using clock_type = std::chrono::steady_clock;
namespace asio = boost::asio;
using mcemu::scripting::RunState;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// A drive bundle of the one test fixture (tests/support/device_fixture.hpp) with a script engine,
// wired as the server wires it: the engine after the bundle's step, the event hand-off after every
// module call.
struct Drive {
  Drive() : drive("MC349", options()) {
    mcemu::scripting::EngineCallbacks cb;
    cb.console = [this](std::string m) { console += m; };
    cb.after_call = [this] { drive.device().handle_events(); };
    engine =
        std::make_unique<mcemu::scripting::ScriptEngine>(io, drive.od(), drive.core(), drive.refgo(), std::move(cb));
  }
  static mcemu::testing::DeviceOptions options() {
    mcemu::testing::DeviceOptions o;
    o.keep_events = false;
    return o;
  }
  void step() {
    drive.step();
    engine->on_step();
  }
  // Starts `source` and steps drive time to its compile; returns once "execute" is printed.
  void start(const std::string& source) {
    engine->upload(source);
    console.clear();
    engine->start();
    for (int i = 0; i < 100; ++i) step();
    while (console.find("code: execute") == std::string::npos) run();
  }
  // An io_context without pending work stops (after a reap); restart it for the next round.
  void run() {
    if (io.stopped()) io.restart();
    io.run_one_for(std::chrono::milliseconds(1));
  }
  asio::io_context io;
  mcemu::testing::DeviceFixture drive;
  std::unique_ptr<mcemu::scripting::ScriptEngine> engine;
  std::string console;
};

// A: calls per second of mc.ReadStatusword() in a tight loop.
double engine_rate(Drive& d, int calls) {
  d.start("import mcdrive as mc\nfor i in range(" + std::to_string(calls) +
          "):\n    mc.ReadStatusword()\nprint('done')\n");
  const auto t0 = clock_type::now();
  while (d.console.find("done") == std::string::npos) d.run();
  const double s = std::chrono::duration<double>(clock_type::now() - t0).count();
  while (d.engine->state() != RunState::off) d.run();
  return calls / s;
}

// B: the same request and reply frames between python3 and a bare Asio peer.
double echo_rate(int calls) {
  int sv[2];
  socketpair(AF_UNIX, SOCK_STREAM, 0, sv);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(sv[1], 4);
    close(sv[0]);
    const std::string prog =
        "import socket,struct\ns=socket.socket(fileno=4)\nst=struct.Struct('<IcHH')\nb=bytearray()\n"
        "for i in range(" +
        std::to_string(calls) +
        "):\n"
        "    s.sendall(st.pack(st.size-4,b'C',4,0))\n"
        "    while True:\n"
        "        if len(b)>=4:\n"
        "            n=struct.unpack_from('<I',b,0)[0]\n"
        "            if len(b)>=4+n:\n"
        "                del b[:4+n]\n                break\n"
        "        b+=s.recv(65536)\n"
        "s.sendall(b'\\x01\\x00\\x00\\x00E')\n";
    execl("/usr/bin/python3", "python3", "-I", "-S", "-c", prog.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(sv[1]);
  asio::io_context io;
  asio::local::stream_protocol::socket sock(io);
  sock.assign(asio::local::stream_protocol(), sv[0]);
  std::vector<char> buf(65536);
  std::string in;
  // a reply frame of the size the engine sends for an int: 'R' + one 'I' value
  const std::string reply = std::string("\x0c\x00\x00\x00R\x01\x00I", 8) + std::string(8, '\0');
  bool done = false;
  clock_type::time_point t0{};
  bool started = false;
  std::function<void()> read;
  read = [&] {
    sock.async_read_some(asio::buffer(buf), [&](const boost::system::error_code& ec, std::size_t n) {
      if (ec) {
        done = true;  // python3 ended early: the round reports what it has
        return;
      }
      if (!started) {
        started = true;
        t0 = clock_type::now();
      }
      in.append(buf.data(), n);
      while (in.size() >= 4) {
        const std::uint32_t len = static_cast<unsigned char>(in[0]) | (static_cast<unsigned char>(in[1]) << 8);
        if (in.size() < 4 + len) break;
        const char kind = in[4];
        in.erase(0, 4 + len);
        if (kind == 'E') {
          done = true;
          return;
        }
        ::send(sv[0], reply.data(), reply.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
      }
      read();
    });
  };
  read();
  while (!done && io.run_one() > 0) {
  }
  const double s = std::chrono::duration<double>(clock_type::now() - t0).count();
  waitpid(pid, nullptr, 0);
  return calls / s;
}

// C: stop() of `while True: pass` until the process is reaped.
double stop_latency_ms(Drive& d) {
  d.start("while True:\n    pass\n");
  const auto warm = clock_type::now() + std::chrono::milliseconds(200);
  while (clock_type::now() < warm) d.run();
  const auto t0 = clock_type::now();
  d.engine->stop();
  while (d.engine->live_processes() > 0) d.run();
  return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}

// D: start() until the first statement of the script has printed (drive time stepped at once).
double start_latency_ms(Drive& d) {
  d.engine->upload("print('go')\n");
  d.console.clear();
  const auto t0 = clock_type::now();
  d.engine->start();
  for (int i = 0; i < 100; ++i) d.step();
  while (d.console.find("go") == std::string::npos) d.run();
  const double ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
  while (d.engine->state() != RunState::off) d.run();
  return ms;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const int rounds = argc > 1 ? std::atoi(argv[1]) : 5;
  const int calls = argc > 2 ? std::atoi(argv[2]) : 20000;
  Drive d;
  if (!d.engine->available()) {
    std::printf("script engine unavailable: %s\n", d.engine->engine_version().c_str());
    return 1;
  }
  std::vector<double> a, b, c, e;
  for (int r = 0; r < rounds; ++r) {
    a.push_back(engine_rate(d, calls));
    b.push_back(echo_rate(calls));
    c.push_back(stop_latency_ms(d));
    e.push_back(start_latency_ms(d));
    std::printf("round %d: engine %.0f calls/s, asio echo %.0f round trips/s, stop %.2f ms, start %.1f ms\n", r + 1,
                a.back(), b.back(), c.back(), e.back());
  }
  const double ma = median(a), mb = median(b);
  std::printf("median of %d rounds, %d calls each (%s):\n", rounds, calls, d.engine->engine_version().c_str());
  std::printf("  mcdrive.ReadStatusword() round trips: %.0f /s\n", ma);
  std::printf("  minimal python3 <-> Asio socketpair echo: %.0f /s\n", mb);
  std::printf("  engine / echo: %.0f %%\n", 100.0 * ma / mb);
  std::printf("  stop latency (stop() to reaped), spinning script: %.2f ms\n", median(c));
  std::printf("  start latency (start() to the first print, drive time stepped at once): %.1f ms\n", median(e));
  return 0;
}
