#include "drive/helpers/helpers.hpp"

#include <tuple>

#include "drive/od/objects.hpp"

namespace mcemu::core::helpers {
namespace {

od::AbortCode put(const DriveRef& d, std::uint16_t index, std::uint8_t sub, std::int64_t value) {
  return d.od.write(index, sub, od::Value{value}, d.origin);
}

std::int64_t get(const DriveRef& d, std::uint16_t index, std::uint8_t sub = 0) {
  auto r = d.od.read_number(index, sub);
  return r.ok() ? *r : 0;
}

// Upper-case hex of `digits` digits ("609A", "00").
std::string hex(std::uint32_t v, int digits) {
  static constexpr char k_hex[] = "0123456789ABCDEF";
  std::string s(static_cast<std::size_t>(digits), '0');
  for (int i = 0; i < digits; ++i) s[static_cast<std::size_t>(digits - 1 - i)] = k_hex[(v >> (4 * i)) & 0xF];
  return s;
}

std::uint16_t controlword(const DriveRef& d) { return static_cast<std::uint16_t>(get(d, 0x6040)); }

// "Applied at once for helpers" (§12): write 6060h and switch the mode before the next edge.
od::AbortCode ensure_mode(const DriveRef& d, std::int8_t mode) {
  if (get(d, 0x6061) == mode && get(d, 0x6060) == mode) return od::AbortCode::none;
  if (const auto c = put(d, 0x6060, 0, mode); c != od::AbortCode::none) return c;
  d.core.apply_mode_switch_now();
  return od::AbortCode::none;
}

}  // namespace

std::int32_t write_object(const DriveRef& d, std::uint16_t index, std::uint8_t sub, std::int64_t value) {
  return static_cast<std::int32_t>(od::to_u32(put(d, index, sub, value)));
}

std::int32_t read_object(const DriveRef& d, std::uint16_t index, std::uint8_t sub) {
  auto r = d.od.read_number(index, sub);
  if (!r.ok()) return static_cast<std::int32_t>(od::to_u32(r.error()));
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(*r));
}

void write_control(const DriveRef& d, std::uint16_t cw) { put(d, 0x6040, 0, cw); }

std::uint16_t read_statusword(const DriveRef& d) { return static_cast<std::uint16_t>(get(d, 0x6041)); }

bool enable_drive(const DriveRef& d) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  if (chk_enabled(d)) return true;
  if (d.core.state() == PdsState::fault) {
    write_control(d, 0x0000);
    write_control(d, 0x0080);
  }
  // at most one pass through SOD → RTSO → SO → OE; QSA leaves by 16 or, failing that, by SOD
  for (int i = 0; i < 5 && !chk_enabled(d); ++i) {
    switch (d.core.state()) {
      case PdsState::switch_on_disabled: write_control(d, 0x0006); break;
      case PdsState::ready_to_switch_on: write_control(d, 0x0007); break;
      case PdsState::switched_on: write_control(d, 0x000F); break;
      case PdsState::quick_stop_active:
        write_control(d, 0x000F);
        if (d.core.state() == PdsState::quick_stop_active) write_control(d, 0x0000);
        break;
      default: return false;
    }
  }
  return chk_enabled(d);
}

void power_quit(const DriveRef& d) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  if (d.core.state() == PdsState::fault) {
    if (controlword(d) & 0x0080) write_control(d, 0x0000);
    write_control(d, 0x0080);
  }
  put(d, 0x6060, 0, 0);
  write_control(d, 0x0000);
}

void stop_motion(const DriveRef& d) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  put(d, 0x605A, 0, 6);
  write_control(d, static_cast<std::uint16_t>((controlword(d) & ~0x0004) | 0x0002));
}

void continue_motion(const DriveRef& d) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  if (d.core.state() != PdsState::quick_stop_active) return;
  write_control(d, static_cast<std::uint16_t>((controlword(d) | 0x000F) & ~0x0080));
  d.core.resume_interrupted_motion();
}

bool autoenable(const DriveRef& d) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  struct StepTo {
    std::uint16_t cw;
    PdsState expect;
  };
  const StepTo to_rtso{0x0006, PdsState::ready_to_switch_on};
  const StepTo to_so{0x0007, PdsState::switched_on};
  const StepTo to_oe{0x000F, PdsState::operation_enabled};
  const auto run = [&](std::initializer_list<StepTo> steps) {
    for (const auto& s : steps) {
      write_control(d, s.cw);
      if (d.core.state() != s.expect) return false;
    }
    return true;
  };
  switch (d.core.state()) {
    case PdsState::operation_enabled: return true;
    case PdsState::switch_on_disabled: return run({to_rtso, to_so, to_oe});
    case PdsState::ready_to_switch_on: return run({to_so, to_oe});
    case PdsState::switched_on:
    case PdsState::quick_stop_active: return run({to_oe});
    default: return false;
  }
}

namespace {

od::AbortCode go_pos(const DriveRef& d, std::int32_t value, std::uint16_t arm, std::uint16_t fire) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  if (const auto c = ensure_mode(d, 1); c != od::AbortCode::none) return c;
  const bool enabled = autoenable(d);
  // 607Ah is written even when AUTOENABLE failed: the target is kept for a later start (§12,
  // refgo.md §7.2).
  if (const auto c = put(d, 0x607A, 0, value); c != od::AbortCode::none) return c;
  if (!enabled || d.core.state() != PdsState::operation_enabled) return od::AbortCode::device_state;
  write_control(d, arm);
  write_control(d, fire);
  return od::AbortCode::none;
}

}  // namespace

od::AbortCode go_pos_abs(const DriveRef& d, std::int32_t position) { return go_pos(d, position, 0x002F, 0x003F); }

od::AbortCode go_pos_rel(const DriveRef& d, std::int32_t distance) { return go_pos(d, distance, 0x006F, 0x007F); }

od::AbortCode go_vel(const DriveRef& d, std::int32_t velocity) {
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  if (const auto c = ensure_mode(d, 3); c != od::AbortCode::none) return c;
  if (!autoenable(d)) return od::AbortCode::device_state;
  if (const std::uint16_t cw = controlword(d); cw & 0x0100) write_control(d, static_cast<std::uint16_t>(cw & ~0x0100));
  return put(d, 0x60FF, 0, velocity);
}

std::string describe(const HelperResult& r) {
  if (r.ok()) return "ok";
  const std::string code = hex(od::to_u32(r.code), 8) + "h";
  if (!r.refused) {
    return (r.code == od::AbortCode::device_state ? "Operation enabled not reached, " : "refused, ") + code;
  }
  return hex(r.refused->index, 4) + "h." + hex(r.refused->sub, 2) + "h := " + std::to_string(r.refused->value) +
         " refused, " + code;
}

HelperResult go_home(const DriveRef& d, std::int8_t method, std::uint32_t speed, std::uint32_t acceleration,
                     std::int32_t offset) {
  const auto refused = [](od::AbortCode c, std::uint16_t index, std::uint8_t sub, std::int64_t value) {
    return HelperResult{c, HelperResult::Write{index, sub, value}};
  };
  const od::ObjectDictionary::HelperScope helper(d.od);  // the drive's own sequence (master lint)
  for (const auto& [index, sub, value] : {std::tuple<std::uint16_t, std::uint8_t, std::int64_t>{0x6098, 0, method},
                                          {0x6099, 1, speed},
                                          {0x609A, 0, acceleration},
                                          {0x607C, 0, offset}}) {
    if (const auto c = put(d, index, sub, value); c != od::AbortCode::none) return refused(c, index, sub, value);
  }
  if (const auto c = ensure_mode(d, 6); c != od::AbortCode::none) return refused(c, 0x6060, 0, 6);
  if ((method == 35 || method == 37) && d.core.state() != PdsState::operation_enabled) {
    return HelperResult{d.core.set_home_here(), std::nullopt};
  }
  if (!autoenable(d)) return HelperResult{od::AbortCode::device_state, std::nullopt};
  write_control(d, 0x000F);
  write_control(d, 0x001F);
  return HelperResult{};
}

od::AbortCode set_target_pos(const DriveRef& d, std::int32_t v) { return put(d, 0x607A, 0, v); }
od::AbortCode set_pos_vel(const DriveRef& d, std::uint32_t v) { return put(d, 0x6081, 0, v); }
od::AbortCode set_acc(const DriveRef& d, std::uint32_t v) { return put(d, 0x6083, 0, v); }
od::AbortCode set_dec(const DriveRef& d, std::uint32_t v) { return put(d, 0x6084, 0, v); }
od::AbortCode set_op_mode(const DriveRef& d, std::int8_t v) { return put(d, 0x6060, 0, v); }
od::AbortCode set_torque(const DriveRef& d, std::uint16_t v) { return put(d, 0x6073, 0, v); }
std::int8_t get_op_mode(const DriveRef& d) { return static_cast<std::int8_t>(get(d, 0x6060)); }
std::int32_t get_actual_pos(const DriveRef& d) { return static_cast<std::int32_t>(get(d, 0x6064)); }

bool chk_ready(const DriveRef& d) { return (read_statusword(d) & 0x0408) != 0; }
bool chk_enabled(const DriveRef& d) { return (read_statusword(d) & 0x006F) == 0x0027; }
bool chk_moving(const DriveRef& d) { return (read_statusword(d) & 0x0100) != 0; }
bool chk_error(const DriveRef& d) { return (read_statusword(d) & 0x0008) != 0; }
bool chk_mfr_status(const DriveRef& d, int bit) { return bit >= 0 && bit < 32 && ((get(d, 0x1002) >> bit) & 1) != 0; }

void send_emcy_msg(const DriveRef& d, std::uint32_t error_number, std::uint8_t error_register,
                   std::uint16_t error_code) {
  d.core.send_script_emcy(error_number, error_register, error_code);
}

od::AbortCode store_permanent(const DriveRef& d, od::Done done) {
  return d.od.write(od::k_store_parameters, 1, od::Value{od::k_save_signature}, d.origin, std::move(done));
}

od::AbortCode reset_to_factory(const DriveRef& d, od::Done done) {
  return d.od.write(od::k_restore_defaults, 1, od::Value{od::k_load_signature}, d.origin, std::move(done));
}

}  // namespace mcemu::core::helpers
