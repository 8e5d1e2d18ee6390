#include "drive/core_context.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {

Handles Handles::resolve(const od::ObjectDictionary& od, const model::ModelPreset& preset) {
  const auto h = [&](std::uint16_t i, std::uint8_t s) { return od.handle(i, s); };
  const auto param = [&](std::uint16_t i, std::uint8_t s) {
    Param p;
    p.handle = od.find(i, s);
    if (!p.handle) {
      const auto it = preset.core_constants.find(model::ObjectKey{i, s});
      if (it != preset.core_constants.end()) p.constant = it->second;
    }
    return p;
  };
  Handles r{};
  r.controlword = h(0x6040, 0);
  r.statusword = h(0x6041, 0);
  r.mode = h(0x6060, 0);
  r.mode_display = h(0x6061, 0);
  r.pos_demand_user = h(0x6062, 0);
  r.pos_actual_inc = h(0x6063, 0);
  r.pos_actual_user = h(0x6064, 0);
  r.vel_demand = h(0x606B, 0);
  r.vel_actual = h(0x606C, 0);
  r.current = od.find(0x6078, 0);
  r.pos_demand_inc = h(0x60FC, 0);
  r.inputs = od.find(0x60FD, 0);
  r.error_register = h(0x1001, 0);
  r.mfr_status = od.find(0x1002, 0);
  r.error_code = h(0x603F, 0);
  for (std::uint8_t s = 0; s <= 4; ++s) r.history[s] = h(0x1003, s);
  r.abort_connection_option = param(0x6007, 0);
  r.stroke_option = param(0x6059, 1);
  r.stroke_position = param(0x6059, 2);
  r.stroke_velocity = param(0x6059, 3);
  r.quick_stop_option = h(0x605A, 0);
  r.shutdown_option = h(0x605B, 0);
  r.disable_option = h(0x605C, 0);
  r.halt_option = h(0x605D, 0);
  r.fault_option = h(0x605E, 0);
  r.pos_window = h(0x6067, 0);
  r.pos_window_time = h(0x6068, 0);
  r.vel_window = h(0x606D, 0);
  r.vel_window_time = h(0x606E, 0);
  r.vel_threshold = h(0x606F, 0);
  r.vel_threshold_time = h(0x6070, 0);
  r.max_current = od.find(0x6073, 0);
  r.target_pos = h(0x607A, 0);
  r.home_offset = h(0x607C, 0);
  r.limit_min = h(0x607D, 1);
  r.limit_max = h(0x607D, 2);
  r.polarity = h(0x607E, 0);
  r.max_profile_vel = h(0x607F, 0);
  r.max_motor_speed = h(0x6080, 0);
  r.profile_vel = h(0x6081, 0);
  r.profile_acc = h(0x6083, 0);
  r.profile_dec = h(0x6084, 0);
  r.quick_stop_dec = h(0x6085, 0);
  r.enc_inc = h(0x608F, 1);
  r.enc_rev = h(0x608F, 2);
  r.gear_motor = h(0x6091, 1);
  r.gear_shaft = h(0x6091, 2);
  r.feed = h(0x6092, 1);
  r.feed_shaft = h(0x6092, 2);
  r.homing_method = h(0x6098, 0);
  r.homing_speed_switch = h(0x6099, 1);
  r.homing_speed_zero = h(0x6099, 2);
  r.homing_acc = h(0x609A, 0);
  r.max_acc = od.find(0x60C5, 0);
  r.max_dec = od.find(0x60C6, 0);
  r.pos_option = param(0x60F2, 0);
  r.target_vel = h(0x60FF, 0);
  r.supported_modes = h(0x6502, 0);
  r.block_count_max = param(0x3401, 0x01);
  r.block_speed = param(0x3401, 0x02);
  r.temperature = od.find(0x3401, 0x0A);
  r.torque_acc = od.find(0x3401, 0x15);
  r.torque_dec = od.find(0x3401, 0x16);
  r.torque_stall = od.find(0x3401, 0x18);
  r.block_mask = param(0x3401, 0x1A);
  r.virtual_inputs = param(0x3510, 1);
  r.outputs = param(0x60FE, 1);
  for (std::size_t i = 0; i < r.input_function.size(); ++i) {
    r.input_function[i] = param(static_cast<std::uint16_t>(0x3511 + i), 1);
  }
  r.following_error = od.find(0x60F4, 0);
  r.jerk = od.find(0x60A4, 0);
  r.switch_select = od.find(0x60B8, 0);
  r.motor_weight = od.find(0x3300, 0x07);
  r.payload = od.find(0x3301, 0x04);
  return r;
}

std::int64_t CoreContext::demand_inc() const { return round_half_away(gen.out().p) - home_offset_inc; }

double CoreContext::accel_of(od::Handle handle) const {
  return scaling.acceleration_to_inc_s2(static_cast<double>(num(handle)));
}

// 60C5h/60C6h bound the profile where the family has them (a FAULHABER drive has not)
double CoreContext::profile_accel() const {
  return h.max_acc ? std::min(accel_of(h.profile_acc), accel_of(*h.max_acc)) : accel_of(h.profile_acc);
}

double CoreContext::profile_decel() const {
  if (rabbit()) return profile_accel();
  return ramp_decel_6084();
}

double CoreContext::ramp_decel_6084() const {
  return h.max_dec ? std::min(accel_of(h.profile_dec), accel_of(*h.max_dec)) : accel_of(h.profile_dec);
}

double CoreContext::quick_stop_decel() const { return accel_of(h.quick_stop_dec); }

double CoreContext::halt_decel() const {
  const std::int64_t opt = num(h.halt_option);
  return (opt >= 2 && opt <= 4) ? quick_stop_decel() : ramp_decel_6084();
}

double CoreContext::speed_limit() const {
  return std::min(scaling.speed_limit_to_inc_s(static_cast<double>(num(h.max_profile_vel))),
                  scaling.speed_limit_to_inc_s(static_cast<double>(num(h.max_motor_speed))));
}

double CoreContext::jerk() const {
  if (!h.jerk) return 0;
  return scaling.jerk_to_inc_s3(static_cast<double>(num(*h.jerk)));
}

SoftLimits CoreContext::soft_limits() const {
  SoftLimits l;
  l.min_user = num(h.limit_min);
  l.max_user = num(h.limit_max);
  l.on = !(l.min_user == 0 && l.max_user == 0) && l.min_user < l.max_user;
  return l;
}

std::optional<std::pair<std::int64_t, std::int64_t>> CoreContext::limits_raw() const {
  if (rotary_operation()) return std::nullopt;
  const SoftLimits l = soft_limits();
  if (!l.on) return std::nullopt;
  const std::int64_t a = raw_of(scaling.to_inc(l.min_user));
  const std::int64_t b = raw_of(scaling.to_inc(l.max_user));
  return std::pair{std::min(a, b), std::max(a, b)};
}

bool CoreContext::outside_limits() const {
  if (rotary_operation()) return false;
  const SoftLimits l = soft_limits();
  if (!l.on) return false;
  const std::int64_t u = user_of(actual_inc());
  return u < l.min_user || u > l.max_user;
}

}  // namespace mcemu::core
