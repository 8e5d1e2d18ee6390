// Handlers of the RefGo command table (refgo.md §6, §7), one function per command word.
// Each returns the outcome of refgo.md §3/§10; none throws.
#pragma once

#include "protocols/refgo/command.hpp"

namespace mcemu::refgo::cmd {

// commands_object.cpp — OR, OW (§9)
Outcome object_read(Interpreter& in, const Call& c);
Outcome object_write(Interpreter& in, const Call& c);

// commands_status.cpp — TP, TPSR, TS, TI (§8)
Outcome tell_position(Interpreter& in, const Call& c);
Outcome tell_tpsr(Interpreter& in, const Call& c);
Outcome tell_status(Interpreter& in, const Call& c);
Outcome tell_input(Interpreter& in, const Call& c);

// commands_param.cpp — SP, AC, DE, ACV, PO, WA, SO, CO, RW, WT (§7.2, §7.6–§7.8)
Outcome speed(Interpreter& in, const Call& c);
Outcome acceleration(Interpreter& in, const Call& c);
Outcome deceleration(Interpreter& in, const Call& c);
Outcome jerk(Interpreter& in, const Call& c);
Outcome target(Interpreter& in, const Call& c);
Outcome set_output(Interpreter& in, const Call& c);
Outcome clear_output(Interpreter& in, const Call& c);
Outcome repeat_way(Interpreter& in, const Call& c);
Outcome wait_time(Interpreter& in, const Call& c);

// commands_motion.cpp — G, GW, SM, CM, PWC, PQ, REF, JP, JN, RR (§7.1–§7.7)
Outcome go_absolute(Interpreter& in, const Call& c);
Outcome go_relative(Interpreter& in, const Call& c);
Outcome stop_motion(Interpreter& in, const Call& c);
Outcome continue_motion(Interpreter& in, const Call& c);
Outcome power_continue(Interpreter& in, const Call& c);
Outcome power_quit(Interpreter& in, const Call& c);
Outcome home(Interpreter& in, const Call& c);
Outcome jog_positive(Interpreter& in, const Call& c);
Outcome jog_negative(Interpreter& in, const Call& c);
Outcome back_and_forth(Interpreter& in, const Call& c);

}  // namespace mcemu::refgo::cmd
