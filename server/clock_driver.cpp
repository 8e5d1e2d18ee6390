#include "server/clock_driver.hpp"

#include <spdlog/spdlog.h>

namespace mcemu::server {

using clock = std::chrono::steady_clock;
constexpr auto k_step = std::chrono::milliseconds(1);
constexpr int k_max_catch_up = 50;

ClockDriver::ClockDriver(boost::asio::io_context& io, std::function<void()> step)
    : timer_(io), step_(std::move(step)) {}

void ClockDriver::start() {
  running_ = true;
  next_ = clock::now() + k_step;
  arm();
}

void ClockDriver::stop() {
  running_ = false;
  timer_.cancel();
}

void ClockDriver::arm() {
  timer_.expires_at(next_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && running_) on_tick();
  });
}

void ClockDriver::on_tick() {
  const auto now = clock::now();
  int n = 0;
  while (next_ <= now && n < k_max_catch_up) {
    step_();
    ++steps_;
    ++n;
    next_ += k_step;
  }
  if (next_ <= now) {
    const auto lag = std::chrono::duration_cast<std::chrono::milliseconds>(now - next_).count();
    if (now - last_warning_ > std::chrono::seconds(10)) {
      spdlog::warn("simulation is {} ms behind real time (the event loop is overloaded)", lag);
      last_warning_ = now;
    }
  }
  arm();
}

}  // namespace mcemu::server
