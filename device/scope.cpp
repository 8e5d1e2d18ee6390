#include "device/scope.hpp"

#include <algorithm>

#include "device/json_fields.hpp"
#include "drive/od/objects.hpp"

namespace mcemu::device {

using nlohmann::json;

namespace {
std::int32_t read32(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
  const auto v = od.read_number(index, sub);
  return v ? static_cast<std::int32_t>(*v) : 0;
}
}  // namespace

void Scope::on_step(std::uint64_t time_ms, const od::ObjectDictionary& od) {
  if (time_ms % k_sample_ms != 0) return;
  if (!ring_.empty() && time_ms == time_of(ring_.size() - 1)) return;  // already sampled
  ScopeSample s;
  s.pos = read32(od, od::k_position, 0);
  s.vel = read32(od, od::k_velocity, 0);
  s.cur = read32(od, od::k_current, 0);
  s.target = read32(od, od::k_target_position, 0);
  s.sw = static_cast<std::uint16_t>(read32(od, od::k_statusword, 0));
  add(time_ms, s);
}

void Scope::add(std::uint64_t time_ms, const ScopeSample& s) {
  const bool contiguous = !ring_.empty() && time_ms == time_of(ring_.size() - 1) + k_sample_ms;
  if (!contiguous) {
    // A new start: the first sample, a gap, or time going backwards (power cycle).
    ring_.clear();
    first_ms_ = time_ms;
    if (time_ms < next_new_ms_) next_new_ms_ = time_ms;
  }
  ring_.push_back(s);
  if (ring_.size() > k_capacity) {
    ring_.pop_front();
    first_ms_ += k_sample_ms;
  }
}

ScopeBlock Scope::block_from(std::size_t first) const {
  ScopeBlock b;
  b.sample_ms = k_sample_ms;
  b.t0 = ring_.empty() ? 0 : time_of(first);  // an empty block: the time of the next sample
  for (std::size_t i = first; i < ring_.size(); ++i) b.samples.push_back(ring_[i]);
  return b;
}

ScopeBlock Scope::since_ms(std::uint64_t t) const {
  if (ring_.empty() || t <= first_ms_) return block_from(0);
  const std::uint64_t offset = (t - first_ms_ + k_sample_ms - 1) / k_sample_ms;
  return block_from(static_cast<std::size_t>(std::min<std::uint64_t>(offset, ring_.size())));
}

ScopeBlock Scope::take_new() {
  ScopeBlock b = since_ms(next_new_ms_);
  if (!ring_.empty()) next_new_ms_ = time_of(ring_.size() - 1) + k_sample_ms;
  return b;
}

json scope_json(const ScopeBlock& b) {
  json pos = json::array(), vel = json::array(), cur = json::array(), target = json::array(), sw = json::array();
  for (const auto& s : b.samples) {
    pos.push_back(s.pos);
    vel.push_back(s.vel);
    cur.push_back(s.cur);
    target.push_back(s.target);
    sw.push_back(s.sw);
  }
  return json{{"sampleMs", b.sample_ms}, {"t0", b.t0}, {"pos", pos}, {"vel", vel}, {"cur", cur},
              {"target", target},        {"sw", sw}};
}

std::string scope_message(const ScopeBlock& b) {
  json j = scope_json(b);
  j["type"] = "scope";
  return dump_json(j);
}

}  // namespace mcemu::device
