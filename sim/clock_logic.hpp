// The decisions of the clock driver, without Asio and without reading a clock (tests drive it with
// a fake wall clock): which steps to run when woken, when to wake next, the manual-clock advance
// queue. server/clock_driver.* is the Asio shell around it.
//
// Time model (drive-core.md §2.2, spec README "Time"): under `real` and `scaled:X` the drive must
// have run floor(X · wall ms since start) steps; when woken it catches up — quiet stretches in one
// skip, at most 50 full steps per wake-up (then it asks to be woken again at once, so network I/O
// is served in between) — and then sleeps until the next step that the drive needs. Under
// `manual` nothing runs except advance() requests, one after the other, in slices of at most 50
// full steps per wake-up; a hold (a script woken by a step, scripting.md §8) pauses the slice.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>

#include "sim/clock_mode.hpp"
#include "sim/steppable.hpp"

namespace mcemu::sim {

class ClockLogic {
 public:
  using Wall = std::chrono::nanoseconds;  // a monotonic wall clock reading
  static constexpr std::uint64_t k_max_full_per_wake = 50;

  struct Next {
    enum class Kind : std::uint8_t { sleep_until, now, wait } kind = Kind::wait;
    Wall at{0};             // sleep_until: the wall time of the next step the drive needs
    std::uint64_t lag = 0;  // now (real/scaled): steps still behind the wall clock
  };

  ClockLogic(sim::Steppable& target, ClockMode mode) : target_(target), mode_(mode) {}

  const ClockMode& mode() const { return mode_; }
  void start(Wall now);

  // A wake-up (timer, post, client): run what is due, then say when to come back.
  Next on_wake(Wall now);
  // Before a client's input reaches the drive: drive time caught up to the wall clock (bounded as
  // on_wake), and the next step marked as a full one. Returns the new plan.
  Next sync(Wall now);
  // The drive changed outside a step (or has output waiting): the next step is a full one.
  Next touch();
  // What to do next without running anything.
  Next plan() const;

  // Manual clock: queue n steps (1 ≤ n ≤ 3 600 000); `done` runs after the last one. false (and
  // nothing queued) under real/scaled or for n out of range.
  bool request(std::uint64_t n, std::function<void()> done);
  // Manual clock: while `held()` is true, no step runs (checked before a slice and after every
  // full step). The script engine releases with the driver's resume().
  void set_hold(std::function<bool()> held) { held_ = std::move(held); }

  // Steps advanced since start (full + skipped) and full steps run: the clock's own counters.
  std::uint64_t ticks() const { return ticks_; }
  std::uint64_t full_steps() const { return full_; }
  // The wall time at which the `tick`-th step since start is due (real/scaled).
  Wall due_at(std::uint64_t tick) const;
  // Steps due by `now` since start (real/scaled).
  std::uint64_t due(Wall now) const;

 private:
  struct Request {
    std::uint64_t remaining;
    std::function<void()> done;
  };
  bool held() const { return held_ && held_(); }
  void catch_up(Wall now);
  Next run_manual();

  sim::Steppable& target_;
  ClockMode mode_;
  Wall epoch_{0};
  std::uint64_t ticks_ = 0;
  std::uint64_t full_ = 0;
  std::uint64_t behind_ = 0;  // after the last catch-up
  std::deque<Request> queue_;
  std::function<bool()> held_;
  struct Memo {
    std::uint64_t tick;
    Wall epoch;
    Wall at;
  };
  mutable std::optional<Memo> memo_;  // the last due_at(): a pure function of (tick, epoch_, mode_)
};

}  // namespace mcemu::sim
