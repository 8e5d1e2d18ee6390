// DriveCore: the drive differences of a FAULHABER MotionController V3.0 (faulhaber.md §7) and the
// FAULHABER objects the core maintains (§8). Runs only when the preset's family is faulhaber
// (fh_ set); a MovingCap drive never reaches this file.
//
// - 6060h acts inside its write: 6061h shows the new mode before the write returns (§7.1).
// - Limit switches: 2310h.01/.02 masks on the logical inputs (physical XOR 2310h.10) stop motion
//   towards an active switch at 6085h, show as 6041h bit 11 in PP/PV and 2324h.01 bits 6/7, and
//   are the references of homing 17/18 (modes/homing.cpp).
// - Faults: the EMCY code, 2320h bit and error register of fh_faults.hpp; the EMCY bytes are
//   code, 1001h, 2320h (LE), 0, 0, 0; 2321h.01 masks the EMCYs of raised errors.
// - Torque: 6072h and 60E0h/60E1h in ‰ of the rated torque bound the positive/negative torque;
//   6077h shows the actual torque in the same unit.
#include <algorithm>
#include <cmath>

#include "drive/drive_core.hpp"
#include "drive/faulhaber/fh_faults.hpp"

namespace mcemu::core {
namespace {

namespace fh = faulhaber;

std::int64_t as_int(const od::Value& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}

std::uint16_t pin_mask(const std::vector<int>& pins) {
  std::uint16_t mask = 0;
  for (const int n : pins) {
    if (n >= 1 && n <= 16) mask = static_cast<std::uint16_t>(mask | (1u << (n - 1)));
  }
  return mask;
}

double sign_of(double x) { return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0); }

bool has(std::int64_t bits, FaultCause cause) { return ((bits >> fault_info(cause).bit) & 1) != 0; }

}  // namespace

void DriveCore::install_faulhaber_hooks() {
  hook_write(0x6060, 0, [this](od::WriteRequest& req) {
    if (powered_) {
      mode_switch_to(static_cast<std::int8_t>(as_int(req.value)));
      update_statusword();
    }
    return od::AbortCode::none;
  });
  // the OD stores after the hook: the new mask or polarity is applied from the written value
  for (const std::uint8_t sub : {std::uint8_t{0x01}, std::uint8_t{0x02}, std::uint8_t{0x10}}) {
    hook_write(0x2310, sub, [this, sub](od::WriteRequest& req) {
      fh::InputConfig c = fh_input_config();
      const auto v = static_cast<std::uint16_t>(as_int(req.value));
      if (sub == 0x01) c.negative_mask = v;
      if (sub == 0x02) c.positive_mask = v;
      if (sub == 0x10) c.polarity = v;
      fh_apply_input_config(c);
      if (powered_) update_statusword();
      return od::AbortCode::none;
    });
  }
  hook_write(0x2311, 0x04, [this](od::WriteRequest& req) {
    const auto state = static_cast<std::uint16_t>(ctx_.num(fh_->output_state));
    const auto command = static_cast<std::uint16_t>(as_int(req.value));
    put(ctx_.od, fh_->output_state, fh::apply_output_command(state, command, pin_mask(preset_.output_pins)));
    return od::AbortCode::none;
  });
}

void DriveCore::fh_power_on() {
  put(ctx_.od, fh_->output_state, 0);
  fh_publish_inputs();
  fh_publish_status();
}

fh::InputConfig DriveCore::fh_input_config() const {
  fh::InputConfig c;
  c.negative_mask = static_cast<std::uint16_t>(ctx_.num(fh_->negative_mask));
  c.positive_mask = static_cast<std::uint16_t>(ctx_.num(fh_->positive_mask));
  c.polarity = static_cast<std::uint16_t>(ctx_.num(fh_->polarity));
  return c;
}

void DriveCore::fh_publish_inputs() { fh_apply_input_config(fh_input_config()); }

void DriveCore::fh_apply_input_config(const fh::InputConfig& config) {
  // the core's input word has IN n at bit 15 + n (drive-core.md §10.9); 2311h has DigIn n at n − 1
  const auto physical = static_cast<std::uint16_t>((ctx_.inputs >> 16) & 0xFFFF);
  const fh::InputState s = fh::evaluate_inputs(physical, pin_mask(preset_.input_pins), config);
  put(ctx_.od, fh_->physical_inputs, s.physical);
  put(ctx_.od, fh_->logical_inputs, s.logical);
  ctx_.limit_negative = s.limit_negative;
  ctx_.limit_positive = s.limit_positive;
  ctx_.limit_negative_configured = (config.negative_mask & pin_mask(preset_.input_pins)) != 0;
  ctx_.limit_positive_configured = (config.positive_mask & pin_mask(preset_.input_pins)) != 0;
}

std::uint32_t DriveCore::fh_device_status() const {
  const std::int64_t bits = mfr();
  fh::DeviceStatus d;
  d.following_error = has(bits, FaultCause::stroke) || has(bits, FaultCause::external_torque);
  d.limit_positive = ctx_.limit_positive;
  d.limit_negative = ctx_.limit_negative;
  if (!ctx_.rotary_operation()) {
    const SoftLimits l = ctx_.soft_limits();
    if (l.on) {
      const std::int64_t u = ctx_.user_of(ctx_.actual_inc());
      d.soft_limit_positive = u >= l.max_user;
      d.soft_limit_negative = u <= l.min_user;
    }
  }
  d.torque_limited = torque_on_ && plant_out_.torque_limit_last > 0 &&
                     std::fabs(plant_out_.torque_raw_last) >= plant_out_.torque_limit_last;
  d.temperature_warning = fh_temperature_warning_;
  d.temperature_error = has(bits, FaultCause::over_temperature) || has(bits, FaultCause::i2t);
  d.over_voltage = has(bits, FaultCause::over_voltage);
  d.under_voltage = has(bits, FaultCause::under_voltage);
  return fh::device_status_word(d);
}

void DriveCore::fh_publish_status() {
  const auto bits = static_cast<std::uint32_t>(mfr());
  put(ctx_.od, fh_->error_word, fh::error_word(bits, fh_temperature_warning_));
  put(ctx_.od, fh_->device_status, fh_device_status());
}

bool DriveCore::fh_emcy_enabled(int error_bit) const {
  return error_bit >= 0 && ((ctx_.num(fh_->emcy_mask) >> error_bit) & 1) != 0;
}

void DriveCore::fh_raise(FaultCause cause, std::int64_t next_bits) {
  auto& od = ctx_.od;
  const fh::FhFault& f = fh::fh_fault(cause);
  const auto bits = static_cast<std::uint32_t>(next_bits);
  const std::uint8_t reg = fh::error_register(bits, fh_temperature_warning_);
  const std::uint16_t word = fh::error_word(bits, fh_temperature_warning_);
  set_mfr(next_bits);
  od.set(ctx_.h.error_register, od::Value{std::int64_t{reg}});
  put(od, fh_->error_word, word);
  od.set(ctx_.h.error_code, od::Value{std::int64_t{f.code}});
  record_history(f.code);
  ctx_.emit(FaultRaised{cause, f.code});
  if (fh_emcy_enabled(f.error_bit)) ctx_.emit(Emcy{f.code, reg, fh::emcy_data(word)});
}

void DriveCore::fh_fault_reset_done(std::int64_t bits) {
  const auto b = static_cast<std::uint32_t>(bits);
  const std::uint8_t reg = fh::error_register(b, fh_temperature_warning_);
  const std::uint16_t word = fh::error_word(b, fh_temperature_warning_);
  ctx_.od.set(ctx_.h.error_register, od::Value{std::int64_t{reg}});
  put(ctx_.od, fh_->error_word, word);
  set_state(PdsState::switch_on_disabled, 15);
  ctx_.emit(FaultResetDone{});
  ctx_.emit(Emcy{0x0000, reg, fh::emcy_data(word)});  // "error reset" (faulhaber.md §6)
}

void DriveCore::fh_check_temperature_warning() {
  const bool warn = round_half_away(temperature_c()) >= fh::k_temperature_warning_deg_c;
  if (warn == fh_temperature_warning_) return;
  fh_temperature_warning_ = warn;
  const auto bits = static_cast<std::uint32_t>(mfr());
  const std::uint8_t reg = fh::error_register(bits, warn);
  const std::uint16_t word = fh::error_word(bits, warn);
  put(ctx_.od, ctx_.h.error_register, reg);
  put(ctx_.od, fh_->error_word, word);
  if (!fh_emcy_enabled(fh::k_temperature_warning_bit)) return;
  // the warning's own EMCY, and 0000h once it is no longer present (faulhaber.md §6)
  ctx_.emit(Emcy{warn ? fh::k_temperature_warning_code : std::uint16_t{0}, reg, fh::emcy_data(word)});
}

void DriveCore::fh_limit_switch_guard() {
  // homing owns the switches (they are its references); an idle or stopping demand moves nowhere
  if (mode_ == 6 || !(ctx_.limit_negative || ctx_.limit_positive)) return;
  const Generator& g = ctx_.gen;
  double dir = 0;
  if (g.kind() == Generator::Kind::move) {
    dir = sign_of(g.move_target() - g.out().p);
  } else if (g.kind() == Generator::Kind::velocity) {
    dir = sign_of(g.velocity_command().target);
  } else {
    return;
  }
  if (dir == 0) dir = sign_of(g.out().v);
  if ((dir < 0 && ctx_.limit_negative) || (dir > 0 && ctx_.limit_positive))
    ctx_.gen.start_stop(ctx_.quick_stop_decel());
}

std::pair<double, double> DriveCore::fh_torque_limits() const {
  const auto limit = [this](od::Handle direction) {
    const std::int64_t permille = std::min(ctx_.num(fh_->max_torque), ctx_.num(direction));
    return std::min(params_.torque_peak, params_.torque_cont * static_cast<double>(permille) / 1000.0);
  };
  return {limit(fh_->torque_limit_positive), limit(fh_->torque_limit_negative)};
}

}  // namespace mcemu::core
