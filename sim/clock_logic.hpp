// The decisions of the clock driver, without Asio and without reading a clock (tests drive it with
// a fake wall clock): which steps to run when woken, when to wake next, the manual-clock advance
// queue. server/clock_driver.* is the Asio shell around it.
//
// Time model (drive-core.md §2.2, spec README "Time"): under `real` and `scaled:X` the drive must
// have run floor(X · wall ms since start) steps; when woken it catches up — quiet stretches in one
// skip, at most 50 full steps per wake-up and no further full step once the wake-up has taken
// k_max_wall_per_wake of wall time (then it asks to be woken again at once, so network I/O is
// served in between) — and then sleeps until the next step that the drive needs. Under `manual`
// nothing runs except advance() requests, one after the other, in slices bounded the same way; a
// hold (a script woken by a step, scripting.md §8) pauses the slice. Where a slice ends changes no
// step's outcome: every step runs whole, in order (docs/faulhaber.md "Execution model").
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
  // A wake-up runs no further full step once it has taken this long (at least one always runs): a
  // drive whose steps are expensive (an MC BASIC program at a high budget, a big fleet) cannot hold
  // the event loop for 50 of them.
  static constexpr Wall k_max_wall_per_wake = std::chrono::milliseconds(2);

  struct Next {
    enum class Kind : std::uint8_t { sleep_until, now, wait } kind = Kind::wait;
    Wall at{0};             // sleep_until: the wall time of the next step the drive needs
    std::uint64_t lag = 0;  // now (real/scaled): steps still behind the wall clock
  };

  // `clock`: the wall clock (same epoch as the `now` arguments) read after each full step for
  // k_max_wall_per_wake; empty = no bound in wall time (tests of the step counts).
  ClockLogic(sim::Steppable& target, ClockMode mode, std::function<Wall()> clock = {})
      : target_(target), mode_(mode), clock_(std::move(clock)) {}

  const ClockMode& mode() const { return mode_; }
  // `first_step_due` (real and scaled time in the server): the first step is due at `now` instead of
  // one step later, so the drive's power-on initialisation (Not ready to switch on → Switch on
  // disabled, its first step) is done before any client is served, as on a real drive that answers.
  // Ignored under the manual clock, whose steps wait for an advance.
  void start(Wall now, bool first_step_due = false);

  // A wake-up (timer, post, client): run what is due, then say when to come back.
  Next on_wake(Wall now);
  // Before a client's input reaches the drive: drive time caught up to the wall clock (bounded as
  // on_wake; nothing runs while a catch-up is already behind — the posted wake-up goes on with it),
  // and the next step marked as a full one. Returns the new plan. `drive`: the one drive of a fleet
  // the input is for (only its next step is made full); null: the whole target.
  Next sync(Wall now, Steppable* drive = nullptr);
  // The drive changed outside a step (or has output waiting): the next step is a full one. `drive`
  // as for sync(): a client of one drive of 1000 does not make the other 999 step in full.
  Next touch(Steppable* drive = nullptr);
  // Before something outside a step reads or changes a drive without a sync (a script's request):
  // that drive's own time brought up to the clock's — a fleet leaves its quiet drives behind
  // (sim::Fleet). Runs no due step and marks nothing; null: every drive.
  void settle(Steppable* drive = nullptr);
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
  bool over_budget(Wall woke) const { return clock_ && clock_() - woke >= k_max_wall_per_wake; }
  void catch_up(Wall now);
  Next run_manual(Wall now);

  sim::Steppable& target_;
  ClockMode mode_;
  Wall epoch_{0};
  std::uint64_t ticks_ = 0;
  std::uint64_t full_ = 0;
  std::uint64_t behind_ = 0;  // after the last catch-up
  std::deque<Request> queue_;
  std::function<bool()> held_;
  std::function<Wall()> clock_;
  struct Memo {
    std::uint64_t tick;
    Wall epoch;
    Wall at;
  };
  mutable std::optional<Memo> memo_;  // the last due_at(): a pure function of (tick, epoch_, mode_)
};

}  // namespace mcemu::sim
