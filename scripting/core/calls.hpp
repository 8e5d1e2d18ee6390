// The module functions the script engine asks the loop to execute (scripting.md §5, §6): one row
// per function with its IPC id, module, name, argument shape and handler. The table is sent to
// the runner at every start, so the ids live only here. Every handler acts through the drive-core
// helpers (drive-core.md §12) with origin `script`, or through the RefGo interpreter and its
// attachment (refgo.md §5, §12), inside one call: one event-loop turn.
//
// Pure and single-threaded (event-loop thread). Handlers never throw; argument types and counts
// are checked again here (the runner checks them first and raises the MicroPython errors).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "drive/helpers/helpers.hpp"
#include "scripting/core/ipc.hpp"

namespace mcemu::refgo {
class Interpreter;
}

namespace mcemu::scripting {

struct CallContext {
  core::helpers::DriveRef drive;  // origin script
  refgo::Interpreter& refgo;
  // A write refused inside a helper (scripting.md §5.3): skipped silently, but traced.
  std::function<void(std::string text)> refused;
};

using Values = std::vector<ipc::Value>;
// Delivers the reply of a call that answered later (StorePermanent, ResetToFactory, a RefGo OW to
// 1010h/1011h through refgo.cmd). Called at most once, on the event-loop thread.
using Later = std::function<void(Values reply)>;
// The reply, or nullopt when `later` will deliver it.
using Handler = std::optional<Values> (*)(CallContext&, std::span<const ipc::Value> args, Later& later);

struct FunctionRow {
  std::uint16_t id;
  std::string_view module;  // "mcdrive" or "refgo"
  std::string_view name;
  std::string_view args;  // one letter per parameter: 'i' int (i32), 's' text, 'b' bytes-or-text
  std::uint8_t required;  // the rest take the defaults the handler knows
  Handler handler;
};

std::span<const FunctionRow> function_table();
const FunctionRow* find_function(std::uint16_t id);

// Runs one call. A malformed call (unknown id, wrong count or types) answers nullopt with
// `malformed` set — a protocol error of the runner.
std::optional<Values> execute_call(CallContext& ctx, const ipc::Call& call, Later later, bool& malformed);

// refgo.cmd()'s return value for the reply of `line` (scripting.md §6.2): int for TS/TP, int from
// hex for TPSR, the answer line, "" without one, None for unknown/empty lines and error replies.
ipc::Value refgo_cmd_result(std::string_view line, std::string_view reply);

// The table as the runner gets it in the start message: per row id, module, name, args, required.
Values table_values();

}  // namespace mcemu::scripting
