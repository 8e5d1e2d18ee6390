#include "protocols/refgo/programs.hpp"

#include "drive/scaling.hpp"

namespace mcemu::refgo {

namespace {

constexpr std::uint16_t k_target_reached = 0x0400;

// The core reports targets in increments only; its own Scaling converts them back to user units
// with the factor group in force (drive-core.md §3: all conversion in the scaling module).
std::int64_t user_of(const core::helpers::DriveRef& d, std::int64_t inc) {
  const auto num = [&](std::uint16_t i, std::uint8_t s) {
    const auto r = d.od.read_number(i, s);
    return r ? static_cast<std::uint64_t>(*r) : 1;
  };
  core::FactorGroup fg;
  fg.encoder_inc = num(0x608F, 1);
  fg.motor_rev = num(0x608F, 2);
  fg.gear_motor = num(0x6091, 1);
  fg.gear_shaft = num(0x6091, 2);
  fg.feed = num(0x6092, 1);
  fg.feed_shaft = num(0x6092, 2);
  fg.polarity = static_cast<std::uint8_t>(num(0x607E, 0));
  if (core::Scaling::check(fg) != od::AbortCode::none) fg = core::FactorGroup{};
  const auto& p = d.core.plant_params();
  return core::Scaling(fg, p.kind, core::AccelUnit{p.accel_unit_num, p.accel_unit_den}).to_user(inc);
}

}  // namespace

void Programs::stop_all() {
  bf_.reset();
  jog_due_ms_.reset();
}

void Programs::arm_jog(std::uint32_t ms) {
  if (ms == 0) {
    jog_due_ms_.reset();
  } else {
    jog_due_ms_ = drive_.core.time_ms() + ms;
  }
}

std::int64_t Programs::back_and_forth_base() const {
  if (const auto inc = drive_.core.last_setpoint_target_inc()) return user_of(drive_, *inc);
  const auto actual = drive_.od.read_number(0x6064, 0);
  return actual ? *actual : 0;
}

od::AbortCode Programs::move_to(std::int64_t target) {
  OwnWrites own(*this);
  return core::helpers::go_pos_abs(drive_, static_cast<std::int32_t>(target));
}

od::AbortCode Programs::start_back_and_forth(std::int64_t base, std::int64_t way, std::uint32_t wait_ms) {
  bf_ = BackAndForth{base, way, wait_ms, Phase::moving_out, drive_.core.time_ms()};
  const auto code = move_to(base + way);
  if (code != od::AbortCode::none) bf_.reset();
  return code;
}

void Programs::on_step() {
  const std::uint64_t now = drive_.core.time_ms();
  if (jog_due_ms_ && now >= *jog_due_ms_) {
    jog_due_ms_.reset();
    OwnWrites own(*this);
    drive_.od.write(0x60FF, 0, od::Value{std::int64_t{0}}, drive_.origin);
  }
  if (!bf_) return;
  if (drive_.core.state() != core::PdsState::operation_enabled) {
    bf_.reset();
    return;
  }
  const std::uint16_t sw =
      statusword_ ? static_cast<std::uint16_t>(drive_.od.number(*statusword_)) : core::helpers::read_statusword(drive_);
  const bool reached = (sw & k_target_reached) != 0;
  auto& g = *bf_;
  switch (g.phase) {
    case Phase::moving_out:
    case Phase::moving_back:
      // The set-point is accepted inside the write; its target is reached at a later step.
      if (reached && now > g.since_ms) {
        g.phase = g.phase == Phase::moving_out ? Phase::dwell_out : Phase::dwell_back;
        g.since_ms = now;
      }
      break;
    case Phase::dwell_out:
    case Phase::dwell_back:
      if (now - g.since_ms >= g.wait_ms) {
        const bool back = g.phase == Phase::dwell_out;
        g.phase = back ? Phase::moving_back : Phase::moving_out;
        g.since_ms = now;
        if (move_to(back ? g.base : g.base + g.way) != od::AbortCode::none) bf_.reset();
      }
      break;
  }
}

}  // namespace mcemu::refgo
