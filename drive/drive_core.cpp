// DriveCore: construction, hooks of §14, power on, queries and the injection interface (§11.9).
#include "drive/drive_core.hpp"

#include <algorithm>
#include <cmath>

namespace mcemu::core {
namespace {

std::int64_t as_int(const od::Value& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}

}  // namespace

DriveCore::DriveCore(const model::ModelPreset& preset, od::ObjectDictionary& od, const PlantConfig& plant_config)
    : preset_(preset),
      params_(resolve_plant(preset_, plant_config)),
      ctx_(od, preset_, params_),
      plant_(params_),
      thermal_(params_),
      pp_(ctx_),
      pv_(ctx_),
      hm_(ctx_) {
  if (preset_.is_faulhaber()) fh_ = faulhaber::FhHandles::resolve(od);
  update_scaling();
  update_inertia_ctrl(std::nullopt, std::nullopt);
  install_hooks();
  install_read_hooks();
}

DriveCore::~DriveCore() {
  for (const auto& [index, sub] : write_hooks_) ctx_.od.on_write(index, sub, {});
  for (const auto& [index, sub] : read_hooks_) ctx_.od.on_read(index, sub, {});
}

std::int64_t DriveCore::mfr() const { return ctx_.h.mfr_status ? ctx_.od.number(*ctx_.h.mfr_status) : mfr_bits_; }

void DriveCore::set_mfr(std::int64_t bits) {
  if (ctx_.h.mfr_status) {
    ctx_.od.set(*ctx_.h.mfr_status, od::Value{bits});
  } else {
    mfr_bits_ = bits;
  }
}

void DriveCore::hook_write(std::uint16_t index, std::uint8_t sub, od::WriteHook hook) {
  // a hook may change state even when the stored value stays the same: the next step runs in full
  ctx_.od.on_write(index, sub, [this, hook = std::move(hook)](od::WriteRequest& req) {
    settled_ = false;
    return hook(req);
  });
  write_hooks_.emplace_back(index, sub);
}

void DriveCore::hook_read(std::uint16_t index, std::uint8_t sub, od::ReadHook hook) {
  ctx_.od.on_read(index, sub, std::move(hook));
  read_hooks_.emplace_back(index, sub);
}

FactorGroup DriveCore::stored_factor_group() const {
  const auto& h = ctx_.h;
  FactorGroup fg;
  fg.encoder_inc = static_cast<std::uint64_t>(ctx_.num(h.enc_inc));
  fg.motor_rev = static_cast<std::uint64_t>(ctx_.num(h.enc_rev));
  fg.gear_motor = static_cast<std::uint64_t>(ctx_.num(h.gear_motor));
  fg.gear_shaft = static_cast<std::uint64_t>(ctx_.num(h.gear_shaft));
  fg.feed = static_cast<std::uint64_t>(ctx_.num(h.feed));
  fg.feed_shaft = static_cast<std::uint64_t>(ctx_.num(h.feed_shaft));
  fg.polarity = static_cast<std::uint8_t>(ctx_.num(h.polarity));
  return fg;
}

void DriveCore::update_scaling() {
  FactorGroup fg = stored_factor_group();
  // a bulk load may bring an impossible group; keep the identity rather than divide by zero
  if (Scaling::check(fg) != od::AbortCode::none) fg = FactorGroup{};
  ctx_.scaling = Scaling(fg, preset_.kind, AccelUnit{params_.accel_unit_num, params_.accel_unit_den});
}

void DriveCore::update_inertia_ctrl(std::optional<std::int64_t> weight, std::optional<std::int64_t> payload) {
  if (!params_.inertia_ctrl_from_od || !ctx_.h.motor_weight || !ctx_.h.payload) return;
  const std::int64_t w = weight.value_or(ctx_.num(*ctx_.h.motor_weight));
  const std::int64_t p = payload.value_or(ctx_.num(*ctx_.h.payload));
  const double j = static_cast<double>(w + p) / 1000.0;
  plant_.set_inertia_ctrl(j > 0 ? j : params_.inertia_ctrl);
}

void DriveCore::install_hooks() {
  hook_write(0x6040, 0, [this](od::WriteRequest& req) {
    return on_controlword(static_cast<std::uint16_t>(as_int(req.value)),
                          static_cast<std::uint16_t>(as_int(req.stored)));
  });
  // factor group and polarity (§3.1, §3.8): refuse impossible ratios, re-derive user values at once
  struct Sub {
    std::uint16_t index;
    std::uint8_t sub;
  };
  for (const Sub s : {Sub{0x608F, 1}, Sub{0x608F, 2}, Sub{0x6091, 1}, Sub{0x6091, 2}, Sub{0x6092, 1}, Sub{0x6092, 2},
                      Sub{0x607E, 0}}) {
    hook_write(s.index, s.sub, [this, s](od::WriteRequest& req) {
      FactorGroup fg = stored_factor_group();
      const auto v = static_cast<std::uint64_t>(as_int(req.value));
      switch (s.index << 8 | s.sub) {
        case 0x608F01: fg.encoder_inc = v; break;
        case 0x608F02: fg.motor_rev = v; break;
        case 0x609101: fg.gear_motor = v; break;
        case 0x609102: fg.gear_shaft = v; break;
        case 0x609201: fg.feed = v; break;
        case 0x609202: fg.feed_shaft = v; break;
        default: fg.polarity = static_cast<std::uint8_t>(v); break;
      }
      if (const auto code = Scaling::check(fg); code != od::AbortCode::none) return code;
      ctx_.scaling = Scaling(fg, preset_.kind, AccelUnit{params_.accel_unit_num, params_.accel_unit_den});
      if (powered_) write_actuals();
      return od::AbortCode::none;
    });
  }
  if (preset_.is_rabbit()) {
    // decel follows accel (§7.7)
    hook_write(0x6083, 0, [this](od::WriteRequest& req) {
      ctx_.od.set(ctx_.h.profile_dec, req.value);
      return od::AbortCode::none;
    });
    if (ctx_.h.motor_weight && ctx_.h.payload) {
      hook_write(0x3300, 0x07, [this](od::WriteRequest& req) {
        update_inertia_ctrl(as_int(req.value), std::nullopt);
        return od::AbortCode::none;
      });
      hook_write(0x3301, 0x04, [this](od::WriteRequest& req) {
        update_inertia_ctrl(std::nullopt, as_int(req.value));
        return od::AbortCode::none;
      });
    }
  }
  for (std::uint8_t sub : {std::uint8_t{1}, std::uint8_t{2}}) {
    hook_write(0x607D, sub, [this, sub](od::WriteRequest& req) {
      if (!powered_ || state_ != PdsState::operation_enabled || mode_ != 1) return od::AbortCode::none;
      SoftLimits lim;
      lim.min_user = sub == 1 ? as_int(req.value) : ctx_.num(ctx_.h.limit_min);
      lim.max_user = sub == 2 ? as_int(req.value) : ctx_.num(ctx_.h.limit_max);
      lim.on = !(lim.min_user == 0 && lim.max_user == 0) && lim.min_user < lim.max_user;
      pp_.on_limits_changed(lim);
      update_statusword();
      return od::AbortCode::none;
    });
  }
  hook_write(0x60FF, 0, [this](od::WriteRequest& req) {
    if (powered_ && as_int(req.value) != as_int(req.stored) && state_ == PdsState::operation_enabled && mode_ == 3) {
      stroke_hold_ = false;
      pv_.on_run_command();
      update_statusword();
    }
    return od::AbortCode::none;
  });
  if (fh_) install_faulhaber_hooks();
}

void DriveCore::power_on(const PowerOnState& state) {
  settled_ = false;
  powered_ = false;  // the 6040h reset below must not run the state machine
  ctx_.od.set(ctx_.h.controlword, od::Value{std::int64_t{0}});
  powered_ = true;
  ctx_.time_ms = 0;
  reload_parameters();
  const std::int64_t raw = state.raw_position_inc.value_or(params_.power_on_position_inc);
  plant_.reset(raw);
  ctx_.actual_raw_inc = raw;
  ctx_.actual_velocity_inc_s = 0;
  prev_position_inc_ = plant_.position_inc();
  prev_reported_inc_ = raw;
  noise_state_ = params_.noise.seed;
  dc_link_v_ = supply_set_.value_or(params_.supply_nominal_v);
  ctx_.home_offset_inc = params_.absolute_encoder ? state.home_offset_inc : raw;
  ctx_.gen.reset(static_cast<double>(raw));
  demand_prev_ = ctx_.gen.out();
  thermal_.reset(ambient_c_);
  plant_out_ = {};
  current_permille_ = 0;
  state_ = PdsState::not_ready_to_switch_on;
  torque_on_ = false;
  pending_ = Pending::none;
  service_move_ = false;
  stroke_hold_ = false;
  mode_ = 0;
  injected_ &= ~(1u << static_cast<int>(FaultCause::needs_reset));
  deferred_ &= ~(1u << static_cast<int>(FaultCause::needs_reset));
  uv_count_.reset();
  ov_count_.reset();
  block_count_ = following_count_ = 0;
  first_step_ = true;
  pp_.clear();
  pp_.reset_reference();
  hm_.abort();
  hold_timer_.restart();
  hold_reached_ = false;
  auto& od = ctx_.od;
  const auto& h = ctx_.h;
  od.set(h.mode_display, od::Value{std::int64_t{0}});
  set_mfr(0);
  fh_temperature_warning_ = false;
  od.set(h.error_register, od::Value{std::int64_t{0}});
  od.set(h.error_code, od::Value{std::int64_t{0}});
  for (std::size_t s = 1; s < h.history.size(); ++s) od.set(h.history[s], od::Value{std::int64_t{0}});
  od.set(h.history[0], od::Value{std::int64_t{0}});
  od.set(h.supported_modes, od::Value{static_cast<std::int64_t>(preset_.supported_modes)});
  publish_inputs(false);
  write_actuals();
  if (fh_) fh_power_on();
  statusword_ = 0;
  od.set(h.statusword, od::Value{std::int64_t{0}});
}

void DriveCore::reload_parameters() {
  settled_ = false;
  update_scaling();
  update_inertia_ctrl(std::nullopt, std::nullopt);
  if (fh_ && powered_) {
    fh_publish_inputs();  // a bulk load may have brought other 2310h masks or polarity
    update_statusword();
  }
}

void DriveCore::step(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) step();
}

std::int64_t DriveCore::last_internal_target_inc() const { return ctx_.scaling.to_inc(pp_.reference_user()); }

double DriveCore::temperature_c() const {
  return injected(FaultCause::over_temperature) ? 115.0 : thermal_.temperature();
}

double DriveCore::supply_voltage() const {
  if (injected(FaultCause::under_voltage)) return params_.supply_uv_v - 1;
  if (injected(FaultCause::over_voltage)) return params_.supply_ov_v + 1;
  if (params_.regen.enabled && powered_) return dc_link_v_;
  return supply_set_.value_or(params_.supply_nominal_v);
}

std::int64_t DriveCore::raw_position_inc() const {
  return powered_ ? round_half_away(plant_.position_inc()) : ctx_.actual_raw_inc;
}

void DriveCore::apply_mode_switch_now() {
  settled_ = false;
  if (!powered_) return;
  mode_switch();
  update_statusword();
}

void DriveCore::resume_interrupted_motion() {
  settled_ = false;
  if (!powered_ || state_ != PdsState::operation_enabled || pending_ != Pending::none) return;
  if (mode_ == 1 && pp_.resume()) update_statusword();
}

od::AbortCode DriveCore::set_home_here() {
  settled_ = false;
  if (state_ == PdsState::fault_reaction_active || state_ == PdsState::fault) return od::AbortCode::device_state;
  ctx_.home_offset_inc = ctx_.actual_raw_inc - ctx_.scaling.to_inc(ctx_.num(ctx_.h.home_offset));
  pp_.reset_reference();
  if (powered_) {
    write_actuals();
    update_statusword();
  }
  return od::AbortCode::none;
}

void DriveCore::inject(FaultCause cause) {
  settled_ = false;
  const std::uint32_t bit = 1u << static_cast<int>(cause);
  const FaultInfo& info = fault_info(cause);
  if (info.kind == FaultKind::event) {
    if (!powered_ || first_step_ || state_ == PdsState::not_ready_to_switch_on) {
      deferred_ |= bit;
      return;
    }
    raise(cause);
    update_statusword();
    return;
  }
  if (cause == FaultCause::i2t) {
    thermal_.set_energy(thermal_.energy_max());
    return;
  }
  injected_ |= bit;
}

void DriveCore::clear(FaultCause cause) {
  settled_ = false;
  const std::uint32_t bit = 1u << static_cast<int>(cause);
  injected_ &= ~bit;
  deferred_ &= ~bit;
}

void DriveCore::set_supply_voltage(double volts) {
  settled_ = false;
  supply_set_ = volts;
}

void DriveCore::set_ambient_temperature(double deg_c) {
  settled_ = false;
  ambient_c_ = deg_c;
}

void DriveCore::set_external_load(double nm_or_n) {
  settled_ = false;
  plant_.set_external_load(nm_or_n);
}

ObstacleId DriveCore::add_obstacle(const Obstacle& obstacle) {
  settled_ = false;
  return plant_.add_obstacle(obstacle);
}

void DriveCore::remove_obstacle(ObstacleId id) {
  settled_ = false;
  plant_.remove_obstacle(id);
}

bool DriveCore::set_external_input_level(int input, bool high) {
  settled_ = false;
  if (std::find(preset_.input_pins.begin(), preset_.input_pins.end(), input) == preset_.input_pins.end()) return false;
  external_level_[static_cast<std::size_t>(input)] = high;
  if (powered_) publish_inputs(true);
  if (powered_ && fh_) update_statusword();  // 2311h, 2324h.01 and bit 11 inside the call
  return true;
}

bool DriveCore::set_external_input_levels(std::uint32_t levels) {
  settled_ = false;
  for (int n = 1; n <= 32; ++n) {
    if (!((levels >> (n - 1)) & 1u)) continue;
    if (std::find(preset_.input_pins.begin(), preset_.input_pins.end(), n) == preset_.input_pins.end()) return false;
  }
  for (const int n : preset_.input_pins) external_level_[static_cast<std::size_t>(n)] = ((levels >> (n - 1)) & 1u) != 0;
  if (powered_) publish_inputs(true);
  if (powered_ && fh_) update_statusword();
  return true;
}

void DriveCore::connection_lost() {
  settled_ = false;
  if (!powered_) return;
  switch (ctx_.num(ctx_.h.abort_connection_option)) {
    case 1: inject(FaultCause::abort_connection); break;
    case 2: apply_state_command(0x0000); break;
    case 3: apply_state_command(0x0002); break;
    default: return;
  }
  update_statusword();
}

void DriveCore::send_script_emcy(std::uint32_t error_number, std::uint8_t error_register, std::uint16_t error_code) {
  Emcy e{error_code, error_register, {}};
  for (std::size_t i = 0; i < 4; ++i) e.data[i] = static_cast<std::uint8_t>((error_number >> (8 * i)) & 0xFF);
  ctx_.emit(e);
}

void DriveCore::recompute_inputs() {
  settled_ = false;
  if (powered_) publish_inputs(true);
  if (powered_ && fh_) update_statusword();
}

std::vector<Event> DriveCore::drain_events() {
  std::vector<Event> out;
  out.swap(ctx_.events);
  return out;
}

}  // namespace mcemu::core
