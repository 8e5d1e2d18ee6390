#include "server/clock_driver.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>

namespace mcemu::server {

using clock = std::chrono::steady_clock;

// The old contract: a callback that needs every step.
class ClockDriver::Always final : public sim::Steppable {
 public:
  explicit Always(std::function<void()> step) : step_(std::move(step)) {}
  void step() override { step_(); }
  std::uint64_t quiet_steps() const override { return 0; }
  void skip(std::uint64_t) override {}
  void touch() override {}

 private:
  std::function<void()> step_;
};

ClockDriver::ClockDriver(boost::asio::io_context& io, sim::Steppable& target, sim::ClockMode mode)
    : io_(io), timer_(io), logic_(target, mode, [this] { return now(); }) {}

ClockDriver::ClockDriver(boost::asio::io_context& io, std::function<void()> step)
    : always_(std::make_unique<Always>(std::move(step))),
      io_(io),
      timer_(io),
      logic_(*always_, sim::ClockMode{}, [this] { return now(); }) {}

ClockDriver::~ClockDriver() {
  alive_.end();
  stop();
}

sim::ClockLogic::Wall ClockDriver::now() const {
  return std::chrono::duration_cast<sim::ClockLogic::Wall>(clock::now() - epoch_);
}

void ClockDriver::start() {
  running_ = true;
  epoch_ = clock::now();
  logic_.start(now(), true);  // the drive initialised before "ready" is logged (real and scaled time)
  reschedule(logic_.plan());
}

void ClockDriver::stop() {
  running_ = false;
  armed_.reset();
  timer_.cancel();
}

void ClockDriver::sync(sim::Steppable* drive) {
  if (!running_) return;
  reschedule(logic_.sync(now(), drive));
}

void ClockDriver::wake(sim::Steppable* drive) {
  if (!running_) return;
  reschedule(logic_.touch(drive));
}

bool ClockDriver::advance(std::uint64_t ms, std::function<void()> done) {
  if (!logic_.request(ms, std::move(done))) return false;
  if (running_) reschedule(logic_.plan());
  return true;
}

void ClockDriver::reschedule(const sim::ClockLogic::Next& next) {
  if (!running_) return;
  using Kind = sim::ClockLogic::Next::Kind;
  if (next.kind == Kind::now) {
    if (next.lag > sim::ClockLogic::k_max_full_per_wake) {
      const auto t = clock::now();
      if (t - last_warning_ > std::chrono::seconds(10)) {
        spdlog::warn("simulation is {} ms behind real time (the event loop is overloaded)", next.lag);
        last_warning_ = t;
      }
    }
    if (posted_) return;
    posted_ = true;
    boost::asio::post(io_, [this, alive = alive_.watch()] {
      if (!alive) return;
      posted_ = false;
      if (running_) fire();
    });
    return;
  }
  if (next.kind == Kind::wait) {
    if (armed_) {
      armed_.reset();
      timer_.cancel();
    }
    return;
  }
  // sleep_until: re-arm only when the new time is earlier (a later one would fire harmlessly: the
  // wake-up re-plans)
  if (armed_ && *armed_ <= next.at) return;
  armed_ = next.at;
  timer_.expires_at(epoch_ + std::chrono::duration_cast<clock::duration>(next.at));
  timer_.async_wait([this, alive = alive_.watch()](const boost::system::error_code& ec) {
    if (ec || !alive) return;
    armed_.reset();
    if (running_) fire();
  });
}

void ClockDriver::fire() {
  ++wake_ups_;
  reschedule(logic_.on_wake(now()));
}

}  // namespace mcemu::server
