// slow_peers: a healthy RefGo client's latency while hostile peers are connected (issue 12).
//
// Rounds alternate "alone" and "attacked". Attacked = a slowloris on HTTP (32 connections, the
// default limit, each sending one byte of a never-ending request header every 100 ms) and a RefGo
// flooder that sends `TP\r` as fast as mcemu reads it and never reads a reply (refgo.md §2.6: mcemu
// stops reading it at 256 KiB of queued replies). The healthy client is the closed loop of
// load_client.hpp on one connection. Prints the medians of the rounds; goal: attacked p99 within
// 2 × alone p99.
//
// Usage: slow_peers [path/to/mcemu] [seconds per round, default 3] [rounds, default 5]
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "bench/load_client.hpp"

using namespace mcemu::bench;

namespace {

class Attack {
 public:
  Attack(std::uint16_t http_port, std::uint16_t refgo_port) {
    for (int i = 0; i < 32; ++i) slow_.push_back(connect_loopback(http_port));
    flooder_ = connect_loopback(refgo_port);
    const int small = 4096;
    ::setsockopt(flooder_, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
    ::fcntl(flooder_, F_SETFL, O_NONBLOCK);
    thread_ = std::thread([this] { run(); });
  }
  ~Attack() {
    stop_ = true;
    thread_.join();
    for (int fd : slow_) ::close(fd);
    ::close(flooder_);
  }
  std::uint64_t flooded_bytes() const { return flooded_; }

 private:
  void run() {
    static const std::string header = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nX-a: ";
    std::string lines;
    for (int i = 0; i < 1000; ++i) lines += "TP\r";
    std::size_t at = 0;
    auto next_byte = clock_type::now();
    while (!stop_) {
      const ssize_t n = ::send(flooder_, lines.data(), lines.size(), MSG_NOSIGNAL);
      if (n > 0) flooded_ += static_cast<std::uint64_t>(n);
      if (clock_type::now() >= next_byte) {
        const char c = at < header.size() ? header[at] : 'a';
        ++at;
        for (int fd : slow_) (void)::send(fd, &c, 1, MSG_NOSIGNAL);
        next_byte += std::chrono::milliseconds(100);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(n > 0 ? 0 : 1));
    }
  }

  std::vector<int> slow_;
  int flooder_ = -1;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> flooded_{0};
  std::thread thread_;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string binary = argc > 1 ? argv[1] : "build/server/mcemu";
  const auto seconds = std::chrono::milliseconds(argc > 2 ? std::atoi(argv[2]) * 1000 : 3000);
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 5;
  const auto state = std::filesystem::temp_directory_path() / ("mcemu-bench-" + std::to_string(::getpid()));
  Child mcemu;
  start_mcemu(mcemu, binary, {}, state.string());
  const Complete reply = [](const std::string& b) { return !b.empty() && b.back() == '>'; };

  std::printf("slow_peers: %d rounds of %.1f s alone and attacked, alternating; medians of the rounds\n", rounds,
              static_cast<double>(seconds.count()) / 1000.0);
  std::printf("load before: %s\n", load_line().c_str());
  std::vector<double> alone_p99, attacked_p99, alone_p50, attacked_p50, alone_tp, attacked_tp;
  std::uint64_t flooded = 0;
  for (int r = 0; r < rounds; ++r) {
    for (const bool attacked : {r % 2 == 0, r % 2 != 0}) {
      std::unique_ptr<Attack> attack;
      if (attacked) attack = std::make_unique<Attack>(mcemu.ports.at("http"), mcemu.ports.at("refgo"));
      const Stats st = closed_loop(mcemu.ports.at("refgo"), "TP\r", reply, 1, seconds);
      if (attack) flooded += attack->flooded_bytes();
      (attacked ? attacked_p99 : alone_p99).push_back(st.percentile(0.99));
      (attacked ? attacked_p50 : alone_p50).push_back(st.percentile(0.50));
      (attacked ? attacked_tp : alone_tp).push_back(st.throughput());
    }
  }
  std::printf("%-10s %12s %9s %9s\n", "", "requests/s", "p50 us", "p99 us");
  std::printf("%-10s %12.0f %9.1f %9.1f\n", "alone", median(alone_tp), median(alone_p50), median(alone_p99));
  std::printf("%-10s %12.0f %9.1f %9.1f\n", "attacked", median(attacked_tp), median(attacked_p50),
              median(attacked_p99));
  std::printf(
      "p99 attacked / alone: %.2fx (goal <= 2x); the kernel accepted %llu bytes of the flooder's sends "
      "(its socket buffers and what mcemu read before it stopped reading)\n",
      median(attacked_p99) / median(alone_p99), static_cast<unsigned long long>(flooded));
  std::printf("load after: %s\n", load_line().c_str());
  std::filesystem::remove_all(state);
  return 0;
}
