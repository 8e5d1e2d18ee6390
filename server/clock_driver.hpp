// The driver of simulated time (drive-core.md §2.2, spec README "Time", web.md §8.10): the Asio
// shell around ClockLogic. Under --clock real (1 ms steps paced by the wall clock) and
// scaled:X (drive time = X × wall time) it sleeps until the next step the drive needs — an idle
// drive costs no wake-ups — and catches up exactly when woken by that deadline or by a client
// (sync/wake); when behind it runs at most 50 full steps per loop iteration, and no further one
// once the iteration has taken 2 ms (sim::ClockLogic::k_max_wall_per_wake), and logs one warning
// per 10 s naming the lag. Under --clock manual drive time stands still except for advance().
//
// Contract: event-loop thread only; the target (one drive's sim::DriveSteps, or a sim::Fleet) must
// outlive the driver. The composition root calls
//   sync()  before a client's input (RefGo line, SLCAN frame, HTTP request, UDP datagram, a
//           persistence completion) touches or reads the drive — drive time is then current;
//   wake()  after anything outside a step changed the drive or queued output for it (a CANopen
//           node's wake hook, a script's OD write) — cheap: marks the next step full, re-plans;
//   settle() before something outside a step reads or changes the drive without a sync (a
//           script's requests, a wall-clock timer's trace line): a fleet steps its quiet drives
//           lazily (sim::Fleet), and this brings the drive's own time up to the clock's.
// Both name the drive (DriveUnit passes its own): in a fleet only that drive's next step is full,
// and the fleet asks only that drive again whether it is quiet (sim::Fleet). Without a drive:
// every drive (shutdown).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>

#include "base/liveness.hpp"
#include "sim/clock_logic.hpp"
#include "sim/clock_mode.hpp"
#include "sim/steppable.hpp"

namespace mcemu::server {

class ClockDriver {
 public:
  ClockDriver(boost::asio::io_context& io, sim::Steppable& target, sim::ClockMode mode = {});
  // Compatibility: a step callback that needs every step (no idle sleeping), real time.
  ClockDriver(boost::asio::io_context& io, std::function<void()> step);
  ~ClockDriver();
  ClockDriver(const ClockDriver&) = delete;
  ClockDriver& operator=(const ClockDriver&) = delete;

  void start();
  void stop();  // pending advance() requests are dropped (their done never runs)

  // `drive`: the one drive of the fleet the input or change is for (only its next step is full);
  // null: every drive.
  void sync(sim::Steppable* drive = nullptr);
  void wake(sim::Steppable* drive = nullptr);
  void settle(sim::Steppable* drive = nullptr) { logic_.settle(drive); }

  // web.md §8.10: manual clock only, 1 ≤ ms ≤ 3 600 000; false = refused (409 / 400 by the caller).
  // A second call waits for the first; `done` runs on the loop after the last step.
  bool advance(std::uint64_t ms, std::function<void()> done);
  // Scripts under --clock manual (scripting.md §8): while held() answers true no step runs; call
  // resume() when it turns false (the script slept, paused or ended).
  void set_hold(std::function<bool()> held) { logic_.set_hold(std::move(held)); }
  void resume() { reschedule(logic_.plan()); }

  const sim::ClockMode& mode() const { return logic_.mode(); }
  double scale() const { return logic_.mode().scale; }
  std::uint64_t steps() const { return logic_.ticks(); }            // drive ms advanced since start()
  std::uint64_t full_steps() const { return logic_.full_steps(); }  // of which really run
  std::uint64_t wake_ups() const { return wake_ups_; }

 private:
  class Always;
  sim::ClockLogic::Wall now() const;
  void reschedule(const sim::ClockLogic::Next& next);
  void fire();

  std::unique_ptr<Always> always_;  // only with the compatibility constructor
  boost::asio::io_context& io_;
  boost::asio::steady_timer timer_;
  sim::ClockLogic logic_;
  std::chrono::steady_clock::time_point epoch_;
  std::optional<sim::ClockLogic::Wall> armed_;  // the timer's expiry, if armed
  bool posted_ = false;
  bool running_ = false;
  std::uint64_t wake_ups_ = 0;
  std::chrono::steady_clock::time_point last_warning_{};
  base::LivenessToken alive_;  // posted steps and the timer's handler check it
};

}  // namespace mcemu::server
