// The real-time driver of simulated time (drive-core.md §2.2): a steady-clock timer every 1 ms;
// on each firing the step callback runs once per whole millisecond elapsed since the last call,
// at most 50 per firing (one warning per 10 s names the lag).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>

namespace mcemu::server {

class ClockDriver {
 public:
  ClockDriver(boost::asio::io_context& io, std::function<void()> step);
  void start();
  void stop();
  std::uint64_t steps() const { return steps_; }

 private:
  void arm();
  void on_tick();

  boost::asio::steady_timer timer_;
  std::function<void()> step_;
  std::chrono::steady_clock::time_point next_;  // time of the next due step
  std::chrono::steady_clock::time_point last_warning_{};
  std::uint64_t steps_ = 0;
  bool running_ = false;
};

}  // namespace mcemu::server
