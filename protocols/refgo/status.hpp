// The RefGo status answers derived from objects (refgo.md §8): TPSR from 6041h, TS from TPSR, TI
// from 60FDh. Pure functions of the object values; the callers read the objects.
#pragma once

#include <cstdint>
#include <string>

namespace mcemu::refgo {

// CiA 402 power state as encoded in a statusword (drive-core.md §4.1).
enum class PowerState : std::uint8_t { nrtso, sod, rtso, so, oe, qsa, fra, f };
PowerState power_state(std::uint16_t statusword);
// The power stage is on in SO, OE, QSA and FRA (TPSR bit 8).
bool power_stage_on(PowerState s);

// TPSR bits (refgo.md §8.1): 0 ERROR, 1 REF (always), 2 IN MOTION, 3 IN POSITION, 8 voltage.
std::uint32_t tpsr(std::uint16_t statusword);
// TS (refgo.md §8.2): 9 fault, 0 power off, 2 moving, 1 powered and idle.
int simple_status(std::uint32_t tpsr_value);

// TI<n>: "1" if input n (1…10) is set in 60FDh; TI: the ten inputs as "%04x", IN1 = bit 0 (§8.4).
std::string tell_input(std::uint32_t inputs, int n);
std::string tell_inputs(std::uint32_t inputs);

}  // namespace mcemu::refgo
