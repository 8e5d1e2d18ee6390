// The four FAULHABER MotionController V3.0 presets (faulhaber.md §1, §7.3, §8): identity, plant,
// pins and the constants the core uses where the FAULHABER dictionary has no object.
#include <array>

#include "drive/model/model_preset.hpp"

namespace mcemu::model {
namespace {

constexpr std::array<std::string_view, 4> k_fh_names = {"FH_MC5004", "FH_MC5005", "FH_MC5010", "FH_MCS"};

// One reference motor for all four presets [choice, docs/decisions/0008]: the MC 50xx are
// controllers without a motor of their own and differ in their power stage, which a motor of
// this size never saturates; the MCS integrates a 3242 BX4, so a 32 mm brushless servo motor of
// that class is what every preset drives. Rated (continuous) torque is the unit of 6071h/6072h/
// 6077h/60E0h/60E1h (‰ of rated torque, faulhaber.md §7.3).
Plant reference_motor() {
  Plant p;
  p.torque_peak = 0.10;  // N·m, 3 × rated
  p.torque_cont = 0.033;
  p.inertia_motor = 2.6e-6;  // kg·m²
  p.inertia_load = 4.0e-6;   // a small coupled load
  p.viscous = 1.0e-6;        // N·m·s/rad
  p.coulomb = 0.0008;        // N·m
  p.no_load_speed = 7000;    // min⁻¹
  p.velocity_bandwidth_hz = 150;
  p.accel_feedforward = 0.9;
  p.following_error_limit_inc = 0;  // blocked axes are caught by the block detector (8611h)
  p.power_on_position_inc = 0;
  p.moving_threshold = 10;     // min⁻¹, statusword bit 8
  p.absolute_encoder = false;  // incremental encoder: 6064h = 0 after power on
  p.p_idle_w = 1.5;
  p.p_cu_w = 12;
  p.r_th_k_per_w = 4.0;
  p.tau_th_s = 300;
  p.temperature_available = true;
  p.supply_nominal_v = 24;
  p.supply_uv_v = 11;
  p.supply_ov_v = 55;
  // 1 unit of 6083h/6084h/6085h/609Ah = 1 motor revolution/s² (faulhaber.md §7.3 [choice])
  p.rotary_accel_unit_num = 1;
  p.rotary_accel_unit_den = 1;
  return p;
}

ModelPreset faulhaber(std::string_view name) {
  ModelPreset m;
  m.name = std::string(name);
  m.family = Family::faulhaber;
  m.base = Base::faulhaber;
  m.kind = Kind::rotary;
  m.supported_modes = 0x25;  // PP, PV, homing (faulhaber.md §7.2)
  m.encoder_inc = 4096;      // 608Fh.01 (faulhaber.md §7.3 [choice])
  Identity& id = m.identity;
  id.vendor_id = 0x00000147;  // FAULHABER (faulhaber.md §8)
  id.vendor_name = "Dr. Fritz Faulhaber GmbH & Co. KG";
  id.software_version = "0111.02O";
  id.hardware_version = "";
  id.serial = 1;  // config faulhaber.serial
  if (name == "FH_MCS") {
    id.device_name = "MCS 3242 BX4 ET";
    id.product_code = 11601;
    id.revision = 15;
    id.short_name = "MCS";
  } else {
    const std::string digits(name.substr(5));  // "5004", "5005", "5010"
    id.device_name = "MC " + digits;
    id.product_code = 0;
    id.revision = 1;
    id.short_name = "MC" + digits;
  }
  id.display_name = "FAULHABER " + id.device_name;
  m.plant = reference_motor();
  // DigIn1…DigIn8: the bit width of 2310h.01/.02 and 2311h.01/.02 [choice, docs/decisions/0008]
  m.input_pins = {1, 2, 3, 4, 5, 6, 7, 8};
  m.output_pins = {1, 2};  // DigOut1, DigOut2 (the two outputs the public clients switch)
  // The core's block detector (drive-core.md §10.6) without 3401h: 100 ms at < 10 min⁻¹ with the
  // torque at its limit; homing −1…−4 use 2324h.02 instead (faulhaber.md §7.2).
  m.core_constants = {{{0x3401, 0x01}, 100}, {{0x3401, 0x02}, 10}};
  return m;
}

}  // namespace

std::span<const std::string_view> faulhaber_preset_names() { return k_fh_names; }

std::optional<ModelPreset> find_faulhaber_preset(std::string_view name) {
  for (const auto n : k_fh_names) {
    if (n == name) return faulhaber(name);
  }
  return std::nullopt;
}

}  // namespace mcemu::model
