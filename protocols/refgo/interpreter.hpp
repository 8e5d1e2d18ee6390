// The built-in RefGo interpreter (refgo.md §3–§10): executes one request line against the object
// dictionary and the drive core and produces its reply bytes.
//
// Contract:
// - One interpreter per drive, shared by every RefGo connection, the web "RefGo Command" box, the
//   JSON API and scripts (refgo.md §1.4, §12); it holds the interpreter variables that are not per
//   connection (repeat way, wait time).
// - Single-threaded (event-loop thread); pure: no clock, no I/O.
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

#include "drive/od/dictionary.hpp"
#include "protocols/refgo/command.hpp"

namespace mcemu::refgo {

// Interpreter variables (refgo.md §7.7): RAM only, reset at power-up.
struct Variables {
  std::int64_t repeat_way = 0;     // RWAY, i32
  std::uint32_t wait_time_ms = 0;  // WTIME
};

class Interpreter {
 public:
  using Later = std::function<void(std::string reply)>;

  explicit Interpreter(od::ObjectDictionary& od);

  // One line as delivered by the line assembler (control bytes already removed, not over-long).
  std::optional<std::string> execute(std::string_view line, Later later = {});

  // Power-up state of the interpreter variables (persistence.md §7 power cycle).
  void reset();

  od::ObjectDictionary& od() { return od_; }
  Variables& variables() { return vars_; }
  const Variables& variables() const { return vars_; }

 private:
  od::ObjectDictionary& od_;
  Variables vars_;
};

}  // namespace mcemu::refgo
