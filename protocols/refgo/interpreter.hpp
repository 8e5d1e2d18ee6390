// The built-in RefGo interpreter (refgo.md §3–§10): executes one request line against the object
// dictionary and the drive core and produces its reply bytes.
//
// Contract:
// - One interpreter per drive, shared by every RefGo connection, the web "RefGo Command" box, the
//   JSON API and scripts (refgo.md §1.4, §12); it holds the interpreter variables that are not per
//   connection (repeat way, wait time).
// - Single-threaded (event-loop thread); pure: no clock, no I/O. Time is the core's drive time:
//   on_step() must run after every DriveCore::step() (jog timer, Back & Forth).
// - Motion acts only through the core's helpers (drive-core.md §12) with origin `refgo`. Any change
//   of 6040h, 6060h or 60FFh not made by the interpreter's own programs stops Back & Forth and the
//   jog timer (refgo.md §7.7: a motion command from any source); the constructor registers that
//   listener on the dictionary, so the interpreter must outlive every write to it.
// - The attachment (refgo.md §5) decides per line whether the sessions execute it here, forward it
//   to a script, or both; execute() itself never looks at it (refgo.cmd and the web box bypass it).
// - execute() never throws on any input. It returns the complete reply of the line, or nullopt when
//   the reply follows later (an OW to 1010h/1011h/3010h.01 answers when the file is durable,
//   refgo.md §2.5); `later` then receives the reply exactly once, on the event-loop thread. The
//   caller must make `later` safe to call after it has gone away.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "drive/drive_core.hpp"
#include "drive/helpers/helpers.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/refgo/attachment.hpp"
#include "protocols/refgo/command.hpp"
#include "protocols/refgo/programs.hpp"

namespace mcemu::refgo {

// Interpreter variables (refgo.md §7.7): RAM only, reset at power-up.
struct Variables {
  std::int64_t repeat_way = 0;     // RWAY, i32
  std::uint32_t wait_time_ms = 0;  // WTIME
};

class Interpreter {
 public:
  using Later = std::function<void(std::string reply)>;

  Interpreter(od::ObjectDictionary& od, core::DriveCore& core);
  Interpreter(const Interpreter&) = delete;
  Interpreter& operator=(const Interpreter&) = delete;

  // One line as delivered by the line assembler (control bytes already removed, not over-long).
  // `later` is copied only by a command that goes pending (OW of Store/Restore).
  std::optional<std::string> execute(std::string_view line, const Later& later = {});

  // After every core step: the jog timer and the Back & Forth generator.
  void on_step() { programs_.on_step(); }

  // Power-up state: variables back to 0, programs stopped (persistence.md §7 power cycle).
  void reset();

  od::ObjectDictionary& od() { return od_; }
  core::helpers::DriveRef drive() { return {core_, od_, od::Origin::refgo}; }
  Programs& programs() { return programs_; }
  const Programs& programs() const { return programs_; }
  Variables& variables() { return vars_; }
  const Variables& variables() const { return vars_; }
  // A script attached to port 10001 (refgo.md §5); the sessions route their lines through it.
  Attachment& attachment() { return attachment_; }
  const Attachment& attachment() const { return attachment_; }

 private:
  od::ObjectDictionary& od_;
  core::DriveCore& core_;
  Variables vars_;
  Programs programs_;
  Attachment attachment_;
};

}  // namespace mcemu::refgo
