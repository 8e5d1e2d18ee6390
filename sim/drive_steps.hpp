// One drive as the clock sees it (drive-core.md §2.4, iofunc.md §3): the I/O functions (which step
// the drive core) and, in order after them, the parts that follow the drive in the same drive time
// (the bundle's parts, device/parts.hpp: fault-injection durations, the scope, the RefGo programs,
// the event hand-off, the CANopen node, the script timers). Each part says how many steps it can be left alone; the
// drive is quiet for the minimum, and a quiet stretch is skipped in one call.
//
// Contract: pure, single-threaded; holds references (the composition root owns everything and
// keeps it alive). The order of parts is the order of add(). A step after touch() or after any
// change of an OD value since the last step is always a full one, so a part only has to answer for
// its own timers and state.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/od/dictionary.hpp"
#include "iofunc/io_functions.hpp"
#include "sim/steppable.hpp"

namespace mcemu::sim {

// Something stepped once per 1 ms step after the drive core.
class Part {
 public:
  virtual ~Part() = default;
  virtual void step() = 0;
  // How many of the next step() calls would do nothing (k_forever: never needed).
  virtual std::uint64_t quiet_steps() const = 0;
  // n ≤ quiet_steps() steps at once (parts that count their own time advance it here).
  virtual void skip(std::uint64_t n) { (void)n; }
  // Starts loading into the caches the objects step() reads through this part's references (a
  // hint, sim::Steppable::prefetch; changes nothing).
  virtual void prefetch() const {}
};

class DriveSteps final : public Steppable {
 public:
  // `io` may be null (a drive without I/O functions, faulhaber.md): then the core is stepped directly.
  DriveSteps(od::ObjectDictionary& od, iofunc::IoFunctions* io, core::DriveCore& core);
  void add(Part& part) { parts_.push_back(&part); }

  void step() override;
  std::uint64_t quiet_steps() const override;
  void skip(std::uint64_t n) override;
  void touch() override { dirty_ = true; }
  void prefetch(int level) const override;

  // The same in absolute drive time (core time_ms(), which restarts at 0 on a power cycle):
  // the time reached by the next step that must run (k_forever: none), and advancing to t.
  std::uint64_t time_ms() const { return core_.time_ms(); }
  std::uint64_t next_deadline_ms() const;
  Advanced advance_to(std::uint64_t t, std::uint64_t max_full = k_forever);

 private:
  od::ObjectDictionary& od_;
  iofunc::IoFunctions* io_;
  core::DriveCore& core_;
  std::vector<Part*> parts_;
  bool dirty_ = true;
  std::uint64_t generation_ = 0;  // od.generation() at the end of the last step
  bool changed_ = false;          // the last step changed the dictionary
};

// A hand-off run after every full step that needs no step of its own (the shell draining core
// events and diagnostics: EMCY to the CANopen node, UDP notes, LED status).
class HookPart final : public Part {
 public:
  explicit HookPart(std::function<void()> fn) : fn_(std::move(fn)) {}
  void step() override { fn_(); }
  std::uint64_t quiet_steps() const override { return k_forever; }

 private:
  std::function<void()> fn_;
};

// A part given by functions (the CANopen bus of the server, a script timer, tests).
class FunctionPart final : public Part {
 public:
  FunctionPart(std::function<void()> step, std::function<std::uint64_t()> quiet,
               std::function<void(std::uint64_t)> skip = {})
      : step_(std::move(step)), quiet_(std::move(quiet)), skip_(std::move(skip)) {}
  void step() override { step_(); }
  std::uint64_t quiet_steps() const override { return quiet_(); }
  void skip(std::uint64_t n) override {
    if (skip_) skip_(n);
  }

 private:
  std::function<void()> step_;
  std::function<std::uint64_t()> quiet_;
  std::function<void(std::uint64_t)> skip_;
};

// Quiet steps before a deadline of a part that runs after the core's step: the part acts in the
// step that brings drive time `now` to `deadline` (or later).
inline std::uint64_t steps_before(std::uint64_t deadline, std::uint64_t now) {
  return deadline > now ? deadline - now - 1 : 0;
}

}  // namespace mcemu::sim
