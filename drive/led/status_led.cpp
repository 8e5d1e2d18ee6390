#include "drive/led/status_led.hpp"

namespace mcemu::led {
namespace {

std::string hex4(std::uint16_t v) {
  static constexpr char k_digits[] = "0123456789ABCDEF";
  std::string out(4, '0');
  for (int i = 3; i >= 0; --i, v = static_cast<std::uint16_t>(v >> 4))
    out[static_cast<std::size_t>(i)] = k_digits[v & 0xF];
  return out;
}

// floor(a / b) for a signed numerator and a positive divisor
std::int64_t floor_div(std::int64_t a, std::int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

StatusLed::StatusLed(Ipv4 ip) { power_up(ip); }

std::string StatusLed::message(Ipv4 ip, std::optional<std::uint16_t> fault_code) {
  std::string s = "MC+IP";
  for (std::size_t i = 0; i < ip.size(); ++i) {
    if (i > 0) s += '+';
    s += std::to_string(ip[i]);
  }
  if (fault_code) s += "+ERR" + hex4(*fault_code);
  s += ':';
  return s;
}

void StatusLed::power_up(Ipv4 ip) {
  ip_ = ip;
  normal_ = std::make_shared<const Schedule>(make_schedule(message(ip, std::nullopt), k_unit_ms));
  start_ = 0;
  current_ = normal_;
  status_.reset();
  status_text_ = normal_;
}

std::shared_ptr<const Schedule> StatusLed::schedule_for(std::optional<std::uint16_t> code) const {
  if (!code) return normal_;
  if (status_ == code) return status_text_;
  return std::make_shared<const Schedule>(make_schedule(message(ip_, code), k_unit_ms));
}

void StatusLed::set_status(std::uint64_t t, std::optional<std::uint16_t> fault_code) {
  if (fault_code == status_) return;
  // Repetitions that started before t took the status in force until now; the one starting at t
  // (if any) takes the new status.
  const std::uint64_t b1 = start_ + current_->cycle_ms;
  if (b1 < t) {
    const std::uint64_t c = status_text_->cycle_ms;
    start_ = b1 + ((t - 1 - b1) / c) * c;
    current_ = status_text_;
  }
  status_text_ = schedule_for(fault_code);
  status_ = fault_code;
}

StatusLed::View StatusLed::view(std::uint64_t t) const {
  View v;
  const std::uint64_t b1 = start_ + current_->cycle_ms;
  if (t < b1) {
    v.cycle_start_ms = start_;
    v.schedule = current_;
    if (status_text_->text != current_->text) v.next = status_text_;
  } else {
    const std::uint64_t c = status_text_->cycle_ms;
    v.cycle_start_ms = b1 + ((t - b1) / c) * c;
    v.schedule = status_text_;
  }
  const auto cycle = static_cast<std::int64_t>(v.schedule->cycle_ms);
  const std::int64_t d = static_cast<std::int64_t>(t) - static_cast<std::int64_t>(v.cycle_start_ms);
  const auto offset = static_cast<std::uint64_t>(d - floor_div(d, cycle) * cycle);
  v.on = v.schedule->on_at(offset);
  return v;
}

std::vector<Edge> StatusLed::edges(std::uint64_t t, std::int64_t from_ms, std::int64_t to_ms) const {
  std::vector<Edge> out;
  if (to_ms < 0 || to_ms < from_ms) return out;
  from_ms = std::max<std::int64_t>(from_ms, 0);
  const View v = view(t);
  const Schedule& s = *v.schedule;
  const auto cycle = static_cast<std::int64_t>(s.cycle_ms);
  const auto c0 = static_cast<std::int64_t>(v.cycle_start_ms);
  for (std::int64_t k = floor_div(from_ms - c0, cycle);; ++k) {
    const std::int64_t base = c0 + k * cycle;
    if (base > to_ms) break;
    for (std::size_t i = 0; i < s.starts.size(); ++i) {
      const std::int64_t at = base + static_cast<std::int64_t>(s.starts[i]);
      if (at > to_ms) break;
      if (at >= from_ms) out.emplace_back(static_cast<std::uint64_t>(at), i % 2 == 0);
    }
  }
  return out;
}

}  // namespace mcemu::led
