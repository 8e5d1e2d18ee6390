// Simulated time that is asked, not polled (design.md; spec README "Time"; drive-core.md §2): the
// interface the clock driver advances, and the one algorithm that advances it — quiet stretches
// skipped in O(1), full steps bounded per call.
//
// Contract: pure, single-threaded. A Steppable is one drive (DriveSteps) or several (Fleet).
// quiet_steps() = how many of the next 1 ms steps would change nothing but what skip() reproduces;
// skip(n) with n ≤ quiet_steps() leaves exactly the state n step() calls leave. touch() says that
// something outside a step changed (or read) the drive: the next step is a full one. A Fleet skips
// its quiet drives lazily: settle_drive()/settle() bring a drive's own time up to the fleet's before
// anything outside a step reads or changes it (touch_drive() and touch() settle first).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <unordered_map>
#include <vector>

namespace mcemu::sim {

inline constexpr std::uint64_t k_forever = std::numeric_limits<std::uint64_t>::max();

class Steppable {
 public:
  virtual ~Steppable() = default;
  virtual void step() = 0;
  virtual std::uint64_t quiet_steps() const = 0;
  virtual void skip(std::uint64_t n) = 0;
  virtual void touch() = 0;
  // touch() of one drive of this target (a Fleet's member; for a single drive, itself): only that
  // drive's next step is full.
  virtual void touch_drive(Steppable& drive) { drive.touch(); }
  // Brings one drive of this target (a Fleet's member) or every drive up to the target's time: the
  // steps it was left behind while quiet are skipped now. A single drive is always up to date.
  virtual void settle_drive(Steppable& drive) { (void)drive; }
  virtual void settle() {}
  // A hint that step() follows soon: start loading into the caches what a step reads, `level`
  // pointers away from this object (0: the objects it refers to, 1: what those refer to, ...). A
  // caller issues level k one step of another drive after level k - 1 (Fleet::step), so that each
  // level's pointers have arrived. Changes nothing.
  virtual void prefetch(int level) const { (void)level; }
};

struct Advanced {
  std::uint64_t steps = 0;  // ms of drive time advanced (full + skipped)
  std::uint64_t full = 0;   // full steps run
};

// Advances at most `n` ms: quiet stretches by skip(), the rest by step(), at most `max_full` full
// steps. Stops early after a full step when `hold` answers true (a script woken by it, under the
// manual clock). Returns what was done; fewer than n steps only when max_full or hold stopped it.
Advanced advance(Steppable& s, std::uint64_t n, std::uint64_t max_full = k_forever,
                 const std::function<bool()>& hold = {});

// N drives on one clock (spec README --drives): a drive that is quiet while another needs a step
// is not visited at all. It is left behind (its own time stays where it was) and settled later in
// one skip: before its next step, by settle_drive() (the clock's sync and touch of that drive), by
// settle() and touch() (every drive), and by skip() of the whole fleet. One moving drive of 1000
// then costs the fleet one step, not 1000 (issue 26); a reader outside a step must settle first
// (server/clock_driver.hpp: sync() does).
// - Each drive's quiet answer is kept as the fleet tick it is quiet through, and asked again only
//   after the drive stepped or was touched (touch_drive): by the contract above nothing else
//   changes it, and a client of one drive of 1000 then costs one answer, not 1000 (issue 26).
// - While it steps one drive it prefetches the next ones, a level deeper for each drive nearer:
//   1000 drives no longer fit the caches, and a step chases pointers (dictionary, core, parts)
//   the hardware cannot guess (bench/device_bench).
class Fleet final : public Steppable {
 public:
  // Prefetching pays once the drives' working sets no longer fit the caches: at 100 moving drives
  // on the development VM it cost ~5 %, from 300 on it saved 10–20 % (bench/device_bench
  // MovingFleet/N). A fleet of fewer than `prefetch_from` drives does not prefetch.
  static constexpr std::size_t k_prefetch_min_drives = 200;
  explicit Fleet(std::size_t prefetch_from = k_prefetch_min_drives) : prefetch_from_(prefetch_from) {}

  void add(Steppable& drive);
  void step() override;
  std::uint64_t quiet_steps() const override;
  void skip(std::uint64_t n) override;
  void touch() override;
  void touch_drive(Steppable& drive) override;
  void settle_drive(Steppable& drive) override;
  void settle() override;

  static constexpr int k_prefetch_levels = 3;

 private:
  static constexpr std::uint64_t k_unknown = 0;  // ask the drive (it is quiet through tick 0 at most)
  // The last fleet tick drive i is known to be quiet through (k_forever: every tick).
  std::uint64_t quiet_through(std::size_t i) const;
  // Drive i's own time brought to the fleet's: one skip of the steps it was left behind.
  void settle_one(std::size_t i);
  // The same for a caller outside a step (settle_drive, touch_drive).
  void settle_outside(std::size_t i);

  std::size_t prefetch_from_;
  std::vector<Steppable*> drives_;
  std::unordered_map<const Steppable*, std::size_t> index_;
  mutable std::vector<std::uint64_t> quiet_through_;
  std::vector<std::uint64_t> settled_;  // the fleet tick each drive's own time has reached
  std::uint64_t ticks_ = 0;             // steps advanced (full or skipped)
};

}  // namespace mcemu::sim
