// State shared by the drive core and its modes: the OD handles the core resolves once, the current
// scaling, the demand generator, the actual values of the last step and the event queue
// (drive-core.md §1.3). Owned by DriveCore; modes hold a reference. Not a shadow copy of the OD:
// parameters are read from the OD through the handles when they are needed.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "drive/events.hpp"
#include "drive/generator.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/plant_config.hpp"
#include "drive/scaling.hpp"

namespace mcemu::core {

// The core's write of a value it reports (an actual value, an input word): set() only when it
// differs, so an unchanged value costs one read.
inline void put(od::ObjectDictionary& od, od::Handle h, std::int64_t v) {
  if (od.number(h) != v) od.set(h, od::Value{v});
}

// An entry the core reads that a family's dictionary may not have (a FAULHABER drive has no
// 3401h, 3510h, 351xh, 6007h, 6059h, 60F2h, 60FEh): the entry, or the preset's constant
// (ModelPreset::core_constants, else 0). On a MovingCap dictionary every Param has its handle.
struct Param {
  std::optional<od::Handle> handle;
  std::int64_t constant = 0;
};

// Handles of the entries the core reads and writes (§14). Plain handles: every family's dictionary
// has them. Params: read, a constant where absent. Optional handles: used only where present.
struct Handles {
  od::Handle controlword, statusword, mode, mode_display;
  od::Handle pos_demand_user, pos_actual_inc, pos_actual_user, vel_demand, vel_actual;
  od::Handle pos_demand_inc, error_register, error_code;
  std::array<od::Handle, 5> history;  // 1003h.00 … .04
  od::Handle quick_stop_option, shutdown_option, disable_option, halt_option, fault_option;
  od::Handle pos_window, pos_window_time, vel_window, vel_window_time, vel_threshold, vel_threshold_time;
  od::Handle target_pos, home_offset, limit_min, limit_max, polarity;
  od::Handle max_profile_vel, max_motor_speed, profile_vel, profile_acc, profile_dec, quick_stop_dec;
  od::Handle enc_inc, enc_rev, gear_motor, gear_shaft, feed, feed_shaft;
  od::Handle homing_method, homing_speed_switch, homing_speed_zero, homing_acc;
  od::Handle target_vel, supported_modes;
  Param abort_connection_option, stroke_option, stroke_position, stroke_velocity, pos_option;
  Param block_count_max, block_speed, block_mask, virtual_inputs, outputs;
  std::array<Param, 10> input_function;  // 3511h … 351Ah .01
  // written only where present: 6078h, 60FDh, 1002h (else DriveCore keeps the bits), 3401h.0Ah
  std::optional<od::Handle> current, inputs, mfr_status, temperature;
  std::optional<od::Handle> max_acc, max_dec, max_current, torque_acc, torque_dec, torque_stall;
  std::optional<od::Handle> following_error, jerk, switch_select, motor_weight, payload;

  // Throws std::out_of_range when an entry every family has is missing (a broken dictionary).
  static Handles resolve(const od::ObjectDictionary& od, const model::ModelPreset& preset);
};

// Soft position limits 607Dh (§7.10): on when not both 0 and min < max.
struct SoftLimits {
  bool on = false;
  std::int64_t min_user = 0;
  std::int64_t max_user = 0;
};

struct CoreContext {
  CoreContext(od::ObjectDictionary& dict, const model::ModelPreset& model, const PlantParams& plant)
      : od(dict), preset(model), params(plant), h(Handles::resolve(dict, model)), gen(model.is_rabbit()) {}

  od::ObjectDictionary& od;
  const model::ModelPreset& preset;
  const PlantParams& params;
  Handles h;
  Scaling scaling;
  Generator gen;
  std::uint64_t time_ms = 0;
  std::int64_t home_offset_inc = 0;
  std::int64_t actual_raw_inc = 0;   // round(plant position), raw frame
  double actual_velocity_inc_s = 0;  // displacement of the last step / 1 ms
  std::uint32_t inputs = 0;          // 60FDh
  // FAULHABER limit switches (2310h.01/.02 on the logical inputs, faulhaber.md §8)
  bool limit_negative = false;
  bool limit_positive = false;
  bool limit_negative_configured = false;  // 2310h.01 names an existing input
  bool limit_positive_configured = false;
  std::vector<Event> events;

  std::int64_t num(od::Handle handle) const { return od.number(handle); }
  std::int64_t num(const Param& p) const { return p.handle ? od.number(*p.handle) : p.constant; }
  bool faulhaber() const { return preset.is_faulhaber(); }
  void emit(Event e) { events.push_back(std::move(e)); }
  bool rabbit() const { return preset.is_rabbit(); }

  // 6063h frame ↔ raw plant frame
  std::int64_t actual_inc() const { return actual_raw_inc - home_offset_inc; }
  std::int64_t demand_inc() const;  // 60FCh = round(p_demand) − home offset
  std::int64_t raw_of(std::int64_t inc) const { return inc + home_offset_inc; }
  // unwrapped user position of an increment count in the 6063h frame
  std::int64_t user_of(std::int64_t inc) const { return scaling.to_user(inc); }

  // converted parameters (inc/s, inc/s²)
  double accel_of(od::Handle handle) const;
  double profile_accel() const;     // min(6083h, 60C5h)
  double profile_decel() const;     // min(6084h, 60C6h); RABBIT profile segments use profile_accel()
  double ramp_decel_6084() const;   // stop ramps "with 6084h" (limited by 60C6h)
  double quick_stop_decel() const;  // 6085h (not limited, §4.5)
  double halt_decel() const;        // 605Dh: 1 → 6084h, 2/3/4 → 6085h, 0 → as 1
  double speed_limit() const;       // min(607Fh, 6080h)
  double jerk() const;              // 60A4h (RABBIT), 0 = unlimited

  SoftLimits soft_limits() const;
  bool rotary_operation() const { return (num(h.pos_option) & 0xC0) != 0; }
  // Soft limits in raw increments, ordered, when linear operation and limits on.
  std::optional<std::pair<std::int64_t, std::int64_t>> limits_raw() const;
  // Actual position outside active linear soft limits.
  bool outside_limits() const;
  bool input_level(int n) const { return n >= 1 && n <= 10 && (inputs & (1u << (15 + n))) != 0; }
};

}  // namespace mcemu::core
