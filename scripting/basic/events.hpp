// What the MC BASIC interpreter reports to its owner (faulhaber.md §9, issue 25 "Trace"): program
// start, stop, normal end and run-time error, every SETOBJ and every SAVE (AN165 warns about the
// EEPROM's write cycles: each SAVE carries the running count). The server puts them on the trace
// ring's `basic` channel with describe() as the text.
//
// Pure value types; the sink is called synchronously from the interpreter (start/stop/step).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "drive/od/abort_code.hpp"
#include "scripting/basic/storage.hpp"

namespace mcemu::basic {

enum class EventKind : std::uint8_t {
  started,   // slot
  stopped,   // slot; message = why ("stop request", "power cycle", "replaced", …)
  finished,  // slot; the end of the text was reached
  error,     // slot, line, message, code (an OD abort code for GETOBJ/SETOBJ/variable failures)
  setobj,    // line, index, sub, value (as converted to the entry's type), code (none = written)
  save,      // line, saved, save_count (every SAVE since construction, this one included)
};

struct Event {
  EventKind kind = EventKind::started;
  int slot = 0;
  std::uint64_t time_ms = 0;  // drive time of the step (the last step's for start/stop requests)
  std::uint32_t line = 0;
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::int64_t value = 0;
  od::AbortCode code = od::AbortCode::none;
  std::string message{};
  std::vector<SavedVariable> saved{};
  std::uint64_t save_count = 0;
};

using EventSink = std::function<void(const Event&)>;

// One line of text: "start slot 2", "setobj line 12 6040h.00 = 15", "setobj line 3 2310h.01 = 4
// refused 06090030", "save line 7 a=1 b=-2 (#3)", "error line 9: division by zero", …
std::string describe(const Event& e);
std::string_view to_string(EventKind k);

}  // namespace mcemu::basic
