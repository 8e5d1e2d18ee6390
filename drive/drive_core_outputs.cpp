// DriveCore: what the core writes into the OD — inputs 60FDh (§10.9), actual and demand values
// (§7.12), the statusword (§5) — and the mirror entries computed on read (§14.1).
#include <algorithm>
#include <cmath>

#include "drive/drive_core.hpp"

namespace mcemu::core {
namespace {

constexpr std::uint32_t k_input_mask = 0x03FF0000;

}  // namespace

std::uint32_t DriveCore::compute_inputs() const {
  const auto virtual_inputs = static_cast<std::uint32_t>(ctx_.num(ctx_.h.virtual_inputs));
  return (physical_inputs() | virtual_inputs) & k_input_mask;
}

std::uint32_t DriveCore::physical_inputs() const {
  // Input n is high when its external level is, when a position switch on it covers the position,
  // or when it is a combined pin whose output is high. One pass over each source (a step runs this
  // for every drive of a fleet).
  const auto bit = [](int n) { return n >= 1 && n <= 10 ? 1u << (15 + n) : 0u; };
  std::uint32_t physical = 0;
  for (int n = 1; n <= 10; ++n) {
    if (external_level_[static_cast<std::size_t>(n)]) physical |= bit(n);
  }
  const std::int64_t raw = raw_position_inc();  // switches see the mechanics, not the encoder noise
  for (const auto& sw : params_.position_switches) {
    if (raw >= sw.from_inc && raw <= sw.to_inc) physical |= bit(sw.input);
  }
  if (!preset_.combined_pins.empty()) {
    const std::int64_t outputs = ctx_.num(ctx_.h.outputs);
    for (const int n : preset_.combined_pins) {
      if ((outputs >> (15 + n)) & 1) physical |= bit(n);
    }
  }
  return physical;
}

void DriveCore::publish_inputs(bool report) {
  const std::uint32_t word = compute_inputs();
  if (word == ctx_.inputs && (!ctx_.h.inputs || ctx_.od.number(*ctx_.h.inputs) == word)) return;
  const std::uint32_t old = ctx_.inputs;
  ctx_.inputs = word;
  if (ctx_.h.inputs) put(ctx_.od, *ctx_.h.inputs, word);
  if (fh_) fh_publish_inputs();
  if (!report || old == word) return;
  if (observer_) observer_(old, word);
  ctx_.emit(InputsChanged{old, word});
}

void DriveCore::write_actuals() {
  auto& od = ctx_.od;
  const auto& h = ctx_.h;
  const Scaling& sc = ctx_.scaling;
  const std::int64_t actual = ctx_.actual_inc();
  const std::int64_t demand = ctx_.demand_inc();
  std::int64_t actual_user = sc.to_user(actual);
  std::int64_t demand_user = sc.to_user(demand);
  if (ctx_.rotary_operation()) {
    const SoftLimits lim = ctx_.soft_limits();
    const std::int64_t low = lim.on ? lim.min_user : 0;
    const std::int64_t range = lim.on ? lim.max_user - lim.min_user : sc.revolution_user();
    actual_user = low + floor_mod(actual_user - low, range);
    demand_user = low + floor_mod(demand_user - low, range);
  }
  put(od, h.pos_demand_inc, wrap_i32(demand));
  put(od, h.pos_demand_user, wrap_i32(demand_user));
  put(od, h.pos_actual_inc, wrap_i32(actual));
  put(od, h.pos_actual_user, wrap_i32(actual_user));
  if (h.following_error) put(od, *h.following_error, wrap_i32(sc.distance_to_user(demand - actual)));
  write_velocity_objects();
  if (h.current) put(od, *h.current, std::clamp<std::int64_t>(current_permille_, -32768, 32767));
  if (fh_) {
    // 6077h: ‰ of the rated (continuous) torque (faulhaber.md §7.3)
    const double permille = torque_on_ ? 1000.0 * plant_out_.mean_torque / params_.torque_cont : 0.0;
    put(od, fh_->torque_actual, std::clamp<std::int64_t>(round_half_away(permille), -32768, 32767));
  }
  if (h.temperature) {
    const std::int64_t temp =
        params_.temperature_available ? std::clamp<std::int64_t>(round_half_away(temperature_c()), 0, 255) : 0;
    put(od, *h.temperature, temp);
  }
}

void DriveCore::write_velocity_objects() {
  const auto clamp32 = [](std::int64_t v) { return std::clamp<std::int64_t>(v, INT32_MIN, INT32_MAX); };
  put(ctx_.od, ctx_.h.vel_demand, clamp32(ctx_.scaling.velocity_from_inc_s(ctx_.gen.out().v)));
  put(ctx_.od, ctx_.h.vel_actual, clamp32(ctx_.scaling.velocity_from_inc_s(ctx_.actual_velocity_inc_s)));
}

std::uint16_t DriveCore::compose_statusword() const {
  std::uint16_t sw = 0;
  switch (state_) {
    case PdsState::not_ready_to_switch_on: sw = 0x0000; break;
    case PdsState::switch_on_disabled: sw = 0x0040; break;
    case PdsState::ready_to_switch_on: sw = 0x0021; break;
    case PdsState::switched_on: sw = 0x0023; break;
    case PdsState::operation_enabled: sw = 0x0027; break;
    case PdsState::quick_stop_active: sw = 0x0007; break;
    case PdsState::fault_reaction_active: sw = 0x000F; break;
    case PdsState::fault: sw = 0x0008; break;
  }
  if ((mfr() & 0xFFFF0000LL) || fh_temperature_warning_) sw |= 0x0080;
  if (state_ != PdsState::fault &&
      ((torque_on_ && ctx_.gen.active()) || std::fabs(ctx_.actual_velocity_inc_s) > params_.moving_threshold_inc_s)) {
    sw |= 0x0100;
  }
  if (state_ == PdsState::quick_stop_active) {
    if ((quick_stop_option_ == 5 || quick_stop_option_ == 6) && ctx_.gen.finished()) sw |= 0x0400;
    return sw;
  }
  if (state_ != PdsState::operation_enabled) return sw;
  if (pending_ != Pending::none || service_move_) {
    if (ctx_.gen.finished() && pending_ != Pending::none) sw |= 0x0400;
    return sw;
  }
  // FAULHABER: an active limit switch is an internal limit in PP and PV (faulhaber.md §8)
  const bool switch_limit = ctx_.limit_negative || ctx_.limit_positive;
  switch (mode_) {
    case 1:
      if (pp_.target_reached()) sw |= 0x0400;
      if (pp_.internal_limit() || switch_limit) sw |= 0x0800;
      if (pp_.ack()) sw |= 0x1000;
      break;
    case 3:
      if (pv_.target_reached()) sw |= 0x0400;
      if (pv_.internal_limit() || switch_limit) sw |= 0x0800;
      if (pv_.speed_zero()) sw |= 0x1000;
      break;
    case 6:
      switch (hm_.status()) {
        case Homing::Status::idle: sw |= 0x0400; break;
        case Homing::Status::in_progress: break;
        case Homing::Status::attained: sw |= 0x1400; break;
        case Homing::Status::error: sw |= 0x2000; break;
      }
      if (ctx_.outside_limits()) sw |= 0x0800;
      break;
    default:
      if (hold_reached_) sw |= 0x0400;
      break;
  }
  return sw;
}

void DriveCore::update_statusword() {
  if (fh_) fh_publish_status();
  const std::uint16_t next = compose_statusword();
  if (next == statusword_) return;
  const std::uint16_t old = statusword_;
  statusword_ = next;
  put(ctx_.od, ctx_.h.statusword, next);
  if (state_ == PdsState::operation_enabled && (next & 0x0400) && !(old & 0x0400) && (old & 0x006F) == 0x0027) {
    ctx_.emit(TargetReached{mode_});
  }
  if (((next ^ old) & 0x0800) != 0) ctx_.emit(InternalLimit{(next & 0x0800) != 0});
  ctx_.emit(StatuswordChanged{old, next});
}

void DriveCore::install_read_hooks() {
  const auto base = preset_.base;
  const auto number = [](std::int64_t v) { return od::Result<od::Value>(od::Value{v}); };
  if (base == model::Base::mc349 || base == model::Base::mcn23) {
    hook_read(0x3401, 0x0B, [this, number](const od::EntryInfo&) {
      const double i = std::fabs(static_cast<double>(current_permille_)) / 1000.0;
      const double p = plant_out_.mean_power + params_.p_cu_w * i * i;
      return number(std::clamp<std::int64_t>(round_half_away(p), -32768, 32767));
    });
  }
  if (base == model::Base::mc349) {
    hook_read(0x3401, 0x1D, [this, number](const od::EntryInfo&) { return number(wrap_i32(ctx_.actual_inc())); });
  }
  if (preset_.ae_extras) {
    hook_read(0x3401, 0x1F, [this, number](const od::EntryInfo&) {
      const std::int64_t turns =
          ctx_.actual_inc() >= 0 ? ctx_.actual_inc() / 65536 : -((-ctx_.actual_inc() + 65535) / 65536);
      return number(static_cast<std::int16_t>(static_cast<std::uint16_t>(turns)));
    });
    hook_read(0x3401, 0x20,
              [this, number](const od::EntryInfo&) { return number(floor_mod(ctx_.actual_inc(), 65536)); });
  }
  if (base == model::Base::mcn23) {
    hook_read(0x3401, 0x23, [this, number](const od::EntryInfo&) {
      return number(std::max<std::int64_t>(0, round_half_away(temperature_c())));
    });
    hook_read(0x5000, 0x03, [this, number](const od::EntryInfo&) { return number(wrap_i32(ctx_.actual_inc())); });
    hook_read(0x5000, 0x04,
              [this, number](const od::EntryInfo&) { return number(wrap_i32(ctx_.demand_inc() - ctx_.actual_inc())); });
    hook_read(0x5000, 0x05, [this, number](const od::EntryInfo&) {
      return number(std::clamp<std::int64_t>(round_half_away(ctx_.actual_velocity_inc_s), INT32_MIN, INT32_MAX));
    });
    hook_read(0x5002, 0x0E, [this, number](const od::EntryInfo&) { return number(wrap_i32(ctx_.actual_inc())); });
  }
}

}  // namespace mcemu::core
