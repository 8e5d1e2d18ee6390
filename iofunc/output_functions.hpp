// Output functions 1–6 (iofunc.md §5): the level of one output computed from a snapshot of the
// drive taken after the core's step. Pure functions; no OD access, no state.
//
// Units: positions and windows of the records are user units and are converted by the core's
// Scaling (drive-core.md §3; no conversion code here); 6063h, 60FCh and the result registers of
// functions 4/6 are increments.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "drive/scaling.hpp"

namespace mcemu::iofunc {

// One record 3611h … 3614h (sub .01 … .06).
struct OutputConfig {
  int function = 0;                 // .01, 0 … 6
  std::uint16_t config = 0;         // .02: mask, side selection, input number or 255
  std::int64_t right_position = 0;  // .03 (usr)
  std::int64_t left_position = 0;   // .04 (usr)
  std::int64_t right_distance = 0;  // .05 (usr)
  std::int64_t left_distance = 0;   // .06 (usr)
};

// What the output functions look at, read from the OD after step 3 of iofunc.md §3.
struct DriveSnapshot {
  std::uint16_t statusword = 0;                   // 6041h
  std::uint32_t mfr_status = 0;                   // 1002h
  std::int64_t position_user = 0;                 // 6064h
  std::int64_t position_inc = 0;                  // 6063h
  std::int64_t general_reference_inc = 0;         // R for .02 = 0, chosen by 60F2h bits 0–1 (§5.4)
  std::optional<std::int64_t> rotary_period_inc;  // P = inc(rotary range) while 60F2h bits 6–7 ≠ 0
  std::array<std::int64_t, 10> result1{};         // 3511h … 351Ah.03
  std::uint16_t candidates = 0;                   // bit n−1 set: IN n is a feedback candidate (§5.5)
};

// "Drive status OK" of function 5: no fault bit, no warning bit, no 1002h error bit 0–13.
bool drive_ok(const DriveSnapshot& s);

// Level of output k (1 … 4) for a function 1 … 6; false for 0 and anything else (function 0
// outputs show their manual latch bit, which is not this function's business).
bool output_level(const OutputConfig& cfg, int k, const DriveSnapshot& s, const core::Scaling& scaling);

}  // namespace mcemu::iofunc
