#include "sim/clock_logic.hpp"

#include <cmath>

namespace mcemu::sim {
namespace {

constexpr std::uint64_t k_longest_sleep_ticks = 1'000'000'000'000;  // about 31 years of drive ms

}  // namespace

void ClockLogic::start(Wall now, bool first_step_due) {
  epoch_ = now;
  ticks_ = 0;
  behind_ = 0;
  if (first_step_due && mode_.kind != ClockMode::Kind::manual) epoch_ = now - (due_at(1) - now);
}

// long double: exact for the nanosecond counts of any realistic uptime (64-bit mantissa)
std::uint64_t ClockLogic::due(Wall now) const {
  if (mode_.kind == ClockMode::Kind::manual || now <= epoch_) return 0;
  // real time (every client input asks): whole milliseconds, no floating point
  if (mode_.scale == 1.0) return static_cast<std::uint64_t>((now - epoch_).count()) / 1'000'000U;
  const long double ms =
      static_cast<long double>((now - epoch_).count()) / 1e6L * static_cast<long double>(mode_.scale);
  return static_cast<std::uint64_t>(std::floor(ms));
}

ClockLogic::Wall ClockLogic::due_at(std::uint64_t tick) const {
  // a quiet drive asks for the same deadline on every client input (plan() after touch())
  if (memo_ && memo_->tick == tick && memo_->epoch == epoch_) return memo_->at;
  Wall w = epoch_ + Wall(static_cast<std::int64_t>(
                        std::ceil(static_cast<long double>(tick) * 1e6L / static_cast<long double>(mode_.scale))));
  // the divisions may be off by a nanosecond either way
  while (due(w) < tick) w += Wall(1);
  while (w > epoch_ && due(w - Wall(1)) >= tick) w -= Wall(1);
  memo_ = Memo{tick, epoch_, w};
  return w;
}

void ClockLogic::catch_up(Wall now) {
  const std::uint64_t d = due(now);
  const std::uint64_t n = d > ticks_ ? d - ticks_ : 0;
  const sim::Advanced r = sim::advance(target_, n, k_max_full_per_wake, [this, now] { return over_budget(now); });
  ticks_ += r.steps;
  full_ += r.full;
  behind_ = n - r.steps;
}

ClockLogic::Next ClockLogic::plan() const {
  Next next;
  if (mode_.kind == ClockMode::Kind::manual) {
    next.kind = !queue_.empty() && !held() ? Next::Kind::now : Next::Kind::wait;
    return next;
  }
  if (behind_ > 0) {
    next.kind = Next::Kind::now;
    next.lag = behind_;
    return next;
  }
  const std::uint64_t quiet = target_.quiet_steps();
  // "never" (or beyond any realistic uptime): sleep until woken
  if (quiet == sim::k_forever || quiet > k_longest_sleep_ticks) return next;
  next.kind = Next::Kind::sleep_until;
  next.at = due_at(ticks_ + quiet + 1);
  return next;
}

ClockLogic::Next ClockLogic::on_wake(Wall now) {
  if (mode_.kind == ClockMode::Kind::manual) return run_manual(now);
  catch_up(now);
  return plan();
}

ClockLogic::Next ClockLogic::sync(Wall now, Steppable* drive) {
  // Already behind, its catch-up wake-up posted: the client is served at the drive time reached so
  // far instead of waiting for a batch of steps of its own (under load every input would add one).
  if (mode_.kind != ClockMode::Kind::manual && behind_ == 0) catch_up(now);
  return touch(drive);
}

ClockLogic::Next ClockLogic::touch(Steppable* drive) {
  if (drive) {
    target_.touch_drive(*drive);
  } else {
    target_.touch();
  }
  return plan();
}

void ClockLogic::settle(Steppable* drive) {
  if (drive) {
    target_.settle_drive(*drive);
  } else {
    target_.settle();
  }
}

bool ClockLogic::request(std::uint64_t n, std::function<void()> done) {
  if (mode_.kind != ClockMode::Kind::manual || n < 1 || n > k_max_advance_ms) return false;
  queue_.push_back(Request{n, std::move(done)});
  return true;
}

ClockLogic::Next ClockLogic::run_manual(Wall now) {
  if (!queue_.empty() && !held()) {
    Request& r = queue_.front();
    const sim::Advanced a =
        sim::advance(target_, r.remaining, k_max_full_per_wake, [this, now] { return held() || over_budget(now); });
    ticks_ += a.steps;
    full_ += a.full;
    r.remaining -= a.steps;
    // Between slices the drives stand still and may be read without a sync (a script polling its
    // drive time, the advance's own answer): none is left behind.
    target_.settle();
    if (r.remaining == 0) {
      auto done = std::move(r.done);
      queue_.pop_front();
      if (done) done();  // may queue the next request
    }
  }
  return plan();
}

}  // namespace mcemu::sim
