#include "device/scope.hpp"

#include <algorithm>

#include "device/json_fields.hpp"
#include "drive/od/objects.hpp"

namespace mcemu::device {

using nlohmann::json;

ScopeSample Scope::sample_of(const od::ObjectDictionary& od) {
  static constexpr std::array<std::uint16_t, 5> k_objects = {od::k_position, od::k_velocity, od::k_current,
                                                             od::k_target_position, od::k_statusword};
  if (source_ != &od) {
    for (std::size_t i = 0; i < k_objects.size(); ++i) handles_[i] = od.find(k_objects[i], 0);
    source_ = &od;
  }
  const auto read32 = [&](std::size_t i) {
    return handles_[i] ? static_cast<std::int32_t>(od.number(*handles_[i])) : std::int32_t{0};
  };
  ScopeSample s;
  s.pos = read32(0);
  s.vel = read32(1);
  s.cur = read32(2);
  s.target = read32(3);
  s.sw = static_cast<std::uint16_t>(read32(4));
  return s;
}

void Scope::on_step(std::uint64_t time_ms, const od::ObjectDictionary& od) {
  if (time_ms % k_sample_ms != 0) return;
  if (total_ > 0 && time_ms == time_of(total_ - 1)) return;  // already sampled
  add(time_ms, sample_of(od));
}

void Scope::add_run(std::uint64_t time_ms, std::uint64_t count, const ScopeSample& s) {
  if (count == 0) return;
  if (count > k_capacity) {  // only the last 60 s stay
    time_ms += (count - k_capacity) * k_sample_ms;
    count = k_capacity;
  }
  const bool contiguous = total_ > 0 && time_ms == time_of(total_ - 1) + k_sample_ms;
  if (!contiguous) {
    // A new start: the first sample, a gap, or time going backwards (power cycle).
    ring_.clear();
    total_ = 0;
    first_ms_ = time_ms;
    if (time_ms < next_new_ms_) next_new_ms_ = time_ms;
  }
  const auto n = static_cast<std::uint32_t>(count);  // ≤ k_capacity (above)
  if (!ring_.empty() && ring_.back().sample == s) {
    ring_.back().count += n;
  } else {
    ring_.push_back(Run{s, n});
  }
  total_ += static_cast<std::size_t>(count);
  while (total_ > k_capacity) {
    Run& front = ring_.front();
    const std::size_t drop = std::min<std::size_t>(front.count, total_ - k_capacity);
    front.count -= static_cast<std::uint32_t>(drop);
    total_ -= drop;
    first_ms_ += drop * k_sample_ms;
    if (front.count == 0) ring_.pop_front();
  }
}

ScopeBlock Scope::block_from(std::size_t first) const {
  ScopeBlock b;
  b.sample_ms = k_sample_ms;
  b.t0 = total_ == 0 ? 0 : time_of(first);  // an empty block: the time of the next sample
  if (first >= total_) return b;
  b.samples.reserve(total_ - first);
  std::size_t skip = first;
  for (const auto& run : ring_) {
    if (skip >= run.count) {
      skip -= run.count;
      continue;
    }
    b.samples.insert(b.samples.end(), run.count - skip, run.sample);
    skip = 0;
  }
  return b;
}

ScopeBlock Scope::since_ms(std::uint64_t t) const {
  if (total_ == 0 || t <= first_ms_) return block_from(0);
  const std::uint64_t offset = (t - first_ms_ + k_sample_ms - 1) / k_sample_ms;
  return block_from(static_cast<std::size_t>(std::min<std::uint64_t>(offset, total_)));
}

ScopeBlock Scope::take_new() {
  ScopeBlock b = since_ms(next_new_ms_);
  if (total_ > 0) next_new_ms_ = time_of(total_ - 1) + k_sample_ms;
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
