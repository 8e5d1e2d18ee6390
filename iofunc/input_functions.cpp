// IoFunctions: dispatch of input edges and 3510h.02 commands (iofunc.md §4.2, §4.13) and the
// input functions 1–11 (§4.4–§4.12). Every effect is an OD write with origin internal; motion
// goes through the drive-core helpers (drive-core.md §12).
#include <algorithm>
#include <cstdlib>

#include "iofunc/io_functions.hpp"

namespace mcemu::iofunc {
namespace {

namespace helpers = core::helpers;

constexpr bool is_jog(std::int64_t f) { return f == 10 || f == 11; }
constexpr std::int64_t k_pv_supported = 0x04;  // 6502h bit 2

std::string input_name(int n) { return "IN" + std::to_string(n); }

}  // namespace

const IoFunctions::FunctionRow* IoFunctions::function_row(int function) {
  static constexpr std::array<FunctionRow, 8> k_rows = {
      FunctionRow{"none", false, nullptr},
      FunctionRow{"capture 1", false, &IoFunctions::capture1},
      FunctionRow{"capture 2", false, &IoFunctions::capture2},
      FunctionRow{"counter", false, &IoFunctions::count},
      FunctionRow{"timed motion absolute", true, &IoFunctions::move_absolute},
      FunctionRow{"quick stop", false, &IoFunctions::quick_stop},
      FunctionRow{"timed motion relative", true, &IoFunctions::move_relative},
      FunctionRow{"set home", true, &IoFunctions::set_home},
  };
  if (function < 1 || function >= static_cast<int>(k_rows.size())) return nullptr;
  return &k_rows[static_cast<std::size_t>(function)];
}

// §4.2: a 10 or 11 in either byte makes a jog input; otherwise the byte of the edge decides.
void IoFunctions::dispatch_edge(int n, bool rising, std::uint64_t now) {
  const std::int64_t code = num(record(n).function);
  const std::int64_t hi = (code >> 8) & 0xFF;
  const std::int64_t lo = code & 0xFF;
  if (is_jog(hi) || is_jog(lo)) {
    if (rising) {
      jog_start(n, static_cast<int>(is_jog(hi) ? hi : lo));
    } else {
      jog_stop(n);
    }
    return;
  }
  trigger(n, static_cast<int>(rising ? hi : lo), now);
}

// §4.13: function ZZ with the record of input YY; ZZ = 8 teaches YY's target at once.
void IoFunctions::dispatch_command(int n, int function, std::uint64_t now) {
  if (n < 1 || n > 10) return;
  if (function == 8) {
    teach(n);
    return;
  }
  trigger(n, function, now);
}

void IoFunctions::trigger(int n, int function, std::uint64_t now) {
  const FunctionRow* row = function_row(function);
  if (row == nullptr) return;  // 0 and the level functions 8 and 9
  if (function == 4 && teach_active()) {
    teach(n);
    return;
  }
  if (row->delayed) {
    // one timer per input; a new trigger restarts it (§4.7)
    const auto delay = static_cast<std::uint64_t>(std::max<std::int64_t>(num(record(n).delay_ms), 0));
    timers_[static_cast<std::size_t>(n - 1)] = Timer{now + delay, function};
    return;
  }
  (this->*row->act)(n);
}

// §4.3: EnableDrive as ordinary controlword writes; false drops the function.
bool IoFunctions::motion_start(int n) {
  if (helpers::enable_drive(drive())) return true;
  note(core::DiagnosticLevel::warning, input_name(n) + ": input function dropped, the drive could not be enabled (" +
                                           std::string(core::to_string(core_.state())) + ")");
  return false;
}

// §4.1: a parameter > 0 is written to its target object; ≤ 0 leaves the target alone.
void IoFunctions::apply_positive(od::Handle target, od::Handle parameter) {
  const std::int64_t v = num(parameter);
  if (v > 0) put(target, v);
}

void IoFunctions::capture1(int n) { put(record(n).result1, num(h_.position_user)); }

void IoFunctions::capture2(int n) { put(record(n).result2, num(h_.position_user)); }

void IoFunctions::count(int n) { put(record(n).result1, core::wrap_i32(num(record(n).result1) + 1)); }

void IoFunctions::move_absolute(int n) { timed_move(n, false); }

void IoFunctions::move_relative(int n) { timed_move(n, true); }

// §4.7 steps 1–5 (and §4.9 for the relative variant).
void IoFunctions::timed_move(int n, bool relative) {
  if (!motion_start(n)) return;
  jog_owner_.reset();
  const InputRecord& r = record(n);
  apply_positive(h_.profile_velocity, r.speed);
  apply_positive(h_.profile_accel, r.accel);
  apply_positive(h_.profile_decel, r.decel);
  apply_positive(h_.max_current, r.max_current);
  const auto target = static_cast<std::int32_t>(num(r.target));
  const od::AbortCode c = relative ? helpers::go_pos_rel(drive(), target) : helpers::go_pos_abs(drive(), target);
  if (c != od::AbortCode::none) {
    note(core::DiagnosticLevel::warning,
         input_name(n) + ": move not started (abort " + std::to_string(od::to_u32(c)) + ")");
    return;
  }
  if (const auto t = core_.last_setpoint_target_inc()) put(r.result1, core::wrap_i32(*t));
  put(r.result2, core::wrap_i32(num(r.result2) + 1));
  executed_ |= static_cast<std::uint16_t>(1u << (n - 1));
}

// §4.8: 605Ah ← 6; quick stop only from Operation Enabled; every timer and the jog cancelled.
void IoFunctions::quick_stop(int) {
  put(h_.quick_stop_option, 6);
  if (core_.state() == core::PdsState::operation_enabled) helpers::stop_motion(drive());
  cancel_all();
}

// §4.9 function 7: homing with method .09, as GoHome.
void IoFunctions::set_home(int n) {
  const InputRecord& r = record(n);
  const std::int64_t method = num(r.decel);
  if (method == 0 || method < -128 || method > 127) {
    note(core::DiagnosticLevel::warning,
         input_name(n) + ": set home dropped, .09 = " + std::to_string(method) + " is no homing method");
    return;
  }
  if (!motion_start(n)) return;
  jog_owner_.reset();
  apply_positive(h_.max_current, r.max_current);
  const std::int64_t speed = num(r.speed) > 0 ? num(r.speed) : num(h_.homing_speed);
  const std::int64_t accel = num(r.accel) > 0 ? num(r.accel) : num(h_.homing_accel);
  const auto result = helpers::go_home(drive(), static_cast<std::int8_t>(method), static_cast<std::uint32_t>(speed),
                                       static_cast<std::uint32_t>(accel), static_cast<std::int32_t>(num(r.target)));
  if (!result.ok()) {
    note(core::DiagnosticLevel::warning, input_name(n) + ": homing not started, " + helpers::describe(result));
  }
}

// §4.10: the target of input n becomes the actual position.
void IoFunctions::teach(int n) { put(record(n).target, num(h_.position_user)); }

// §4.12 rising edge: velocity mode at ±|.06|; this input becomes the jog owner.
void IoFunctions::jog_start(int n, int function) {
  if ((num(h_.supported_modes) & k_pv_supported) == 0) {
    note(core::DiagnosticLevel::warning, input_name(n) + ": jog dropped, no velocity mode on this model");
    return;
  }
  if (!motion_start(n)) return;
  const InputRecord& r = record(n);
  apply_positive(h_.profile_accel, r.accel);
  apply_positive(h_.max_current, r.max_current);
  const std::int64_t magnitude = std::min<std::int64_t>(std::llabs(num(r.speed)), INT32_MAX);
  const auto velocity = static_cast<std::int32_t>(function == 10 ? magnitude : -magnitude);
  const od::AbortCode c = helpers::go_vel(drive(), velocity);
  if (c != od::AbortCode::none) {
    jog_owner_.reset();
    note(core::DiagnosticLevel::warning,
         input_name(n) + ": jog not started (abort " + std::to_string(od::to_u32(c)) + ")");
    return;
  }
  jog_owner_ = n;
}

// §4.12 falling edge of the owner: brake with .09 to standstill, stay in velocity mode.
void IoFunctions::jog_stop(int n) {
  if (jog_owner_ != n) return;
  jog_owner_.reset();
  if (num(h_.mode_display) != 3) return;
  apply_positive(h_.profile_decel, record(n).decel);
  put(h_.target_velocity, 0);
}

void IoFunctions::cancel_all() {
  timers_ = {};
  jog_owner_.reset();
}

// Any write of 35xxh.01 (§4.1): result registers cleared, timer cancelled, own jog stopped,
// feedback candidacy from executed moves forgotten.
void IoFunctions::on_function_written(int n) {
  const InputRecord& r = record(n);
  put(r.result1, 0);
  put(r.result2, 0);
  timers_[static_cast<std::size_t>(n - 1)].reset();
  executed_ &= static_cast<std::uint16_t>(~(1u << (n - 1)));
  if (jog_owner_ == n) jog_stop(n);
}

}  // namespace mcemu::iofunc
