// The MC BASIC of one FAULHABER drive (faulhaber.md §9.1): eight program slots, the autostart
// number and the one interpreter that runs at most one of them. This is the class the composition
// root owns; it persists nothing itself (program texts, the autostart number and SAVEd variables
// are the owner's to store — see README.md "Wiring").
//
// Contract: pure, single-threaded. Slots are numbered 1 … 8. A slot's state is `empty`, `loaded`,
// `running`, `stopped` (by request or at the end of its text) or `error` (the loader's verdict, or
// a run-time error of its last run). Only `loaded` and `stopped` slots start (§9.1: `empty` and
// `error` answer 409). A power cycle or device reset stops the running program and turns every
// `running`/`stopped`/run-time `error` slot back into `loaded`; load errors stay.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "scripting/basic/interpreter.hpp"
#include "scripting/basic/loader.hpp"

namespace mcemu::basic {

enum class SlotState : std::uint8_t { empty, loaded, running, stopped, error };
std::string_view to_string(SlotState s);  // "empty", "loaded", "running", "stopped", "error"

struct SlotStatus {
  SlotState state = SlotState::empty;
  std::uint32_t line = 0;                    // error: the line (0 = the program as a whole)
  std::string message{};                     // error
  od::AbortCode code = od::AbortCode::none;  // run-time error of an OD access
  bool load_error = false;                   // error: found by the loader (the text must change)
  std::size_t bytes = 0;
};

class Programs {
 public:
  static constexpr int k_slots = 8;

  Programs(od::ObjectDictionary& od, VariableStorage& storage, Settings settings = {}, EventSink sink = {});
  Programs(const Programs&) = delete;  // the interpreter's sink points here
  Programs& operator=(const Programs&) = delete;

  enum class Upload : std::uint8_t { ok, bad_slot, too_large };
  // Stores and loads the text (a running slot is stopped first). ok: the slot is `loaded`, or
  // `error` with the loader's line and message. too_large (> 4096 bytes): nothing changes.
  Upload upload(int slot, std::string_view text);
  // The slot becomes empty (stopped first if it runs). False for a bad slot number.
  bool erase(int slot);

  enum class Start : std::uint8_t { ok, bad_slot, not_startable };
  // Starts the slot (the running program, if another, is stopped first).
  Start start(int slot);
  void stop();  // the running program, if any, stops (`stopped`)

  SlotStatus status(int slot) const;  // a bad slot reads as empty
  std::string_view source(int slot) const;
  int running() const;  // the running slot, 0 = none
  std::optional<std::uint32_t> running_line() const;

  int autostart() const { return autostart_; }
  bool set_autostart(int slot);  // 0 = none, 1 … 8; false otherwise (unchanged)
  // Power loss or device reset: the running program ends ("power cycle").
  void power_cycle();
  // After power on / a device reset: starts the autostart slot if it can start; true if it did.
  bool start_autostart();

  // ---- time (the sim::Part of the drive, after the drive core)
  void step(std::uint64_t now_ms) { interp_.step(now_ms); }
  std::uint64_t quiet_steps() const { return interp_.quiet_steps(); }
  void skip(std::uint64_t n) { interp_.skip(n); }

  Interpreter& interpreter() { return interp_; }
  const Interpreter& interpreter() const { return interp_; }

 private:
  struct Slot {
    std::string source;
    std::optional<Program> program;  // loaded without error
    SlotStatus status;               // when not running
  };
  static bool valid(int slot) { return slot >= 1 && slot <= k_slots; }
  Slot& at(int slot) { return slots_[static_cast<std::size_t>(slot - 1)]; }
  const Slot& at(int slot) const { return slots_[static_cast<std::size_t>(slot - 1)]; }
  void on_event(const Event& e);

  EventSink sink_;
  Interpreter interp_;
  std::array<Slot, k_slots> slots_;
  int autostart_ = 0;
};

}  // namespace mcemu::basic
