// The RefGo interpreter's timed motion programs (refgo.md §7.6, §7.7): the Back & Forth generator
// of RR and the timed stop of JP<t>/JN<t>. Both act only through the core's helpers
// (drive/helpers) and ordinary OD writes, in drive time.
//
// Contract: single-threaded, pure. on_step() runs after every core step. stop_all() is STOPGEN.
// A program's own object writes happen inside an OwnWrites scope, so that the interpreter's change
// listener can tell them from motion commands of other sources (which stop the programs).
#pragma once

#include <cstdint>
#include <optional>

#include "drive/helpers/helpers.hpp"

namespace mcemu::refgo {

class Programs {
 public:
  explicit Programs(core::helpers::DriveRef drive) : drive_(drive), statusword_(drive.od.find(0x6041, 0)) {}

  // Marks the writes made while it lives as the interpreter's own (no self-stop).
  class OwnWrites {
   public:
    explicit OwnWrites(Programs& p) : p_(p) { ++p_.own_depth_; }
    ~OwnWrites() { --p_.own_depth_; }
    OwnWrites(const OwnWrites&) = delete;
    OwnWrites& operator=(const OwnWrites&) = delete;

   private:
    Programs& p_;
  };
  bool own_write() const { return own_depth_ > 0; }

  // STOPGEN (§7.1): stop Back & Forth and cancel a pending timed-jog stop; writes nothing.
  void stop_all();

  // The jog timer (§7.6): 60FFh := 0 `ms` after `now`; 0 disarms.
  void arm_jog(std::uint32_t ms);
  // Back & Forth (§7.7) between `base` and `base + way` with `wait_ms` dwell, starting with the
  // move to base + way. The drive must be OE. Returns the abort code of a refused first move.
  od::AbortCode start_back_and_forth(std::int64_t base, std::int64_t way, std::uint32_t wait_ms);
  // RR's base: the user-unit target of the last accepted PP set-point, or 6064h if none (§7.7).
  std::int64_t back_and_forth_base() const;

  void on_step();

  bool back_and_forth_active() const { return bf_.has_value(); }
  std::optional<std::uint64_t> jog_stop_due_ms() const { return jog_due_ms_; }

 private:
  enum class Phase : std::uint8_t { moving_out, dwell_out, moving_back, dwell_back };
  struct BackAndForth {
    std::int64_t base = 0;
    std::int64_t way = 0;
    std::uint32_t wait_ms = 0;
    Phase phase = Phase::moving_out;
    std::uint64_t since_ms = 0;  // time of the last move start or of reaching the target
  };

  od::AbortCode move_to(std::int64_t target);

  core::helpers::DriveRef drive_;
  std::optional<od::Handle> statusword_;  // 6041h, read every step of a Back & Forth
  std::optional<BackAndForth> bf_;
  std::optional<std::uint64_t> jog_due_ms_;
  int own_depth_ = 0;
};

}  // namespace mcemu::refgo
