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

namespace {

// The fields of a run that differ from the run before, and a count above 1.
enum FieldBit : std::uint8_t { k_pos = 1, k_vel = 2, k_cur = 4, k_target = 8, k_sw = 16, k_count = 32 };

void put_varint(std::deque<std::uint8_t>& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<std::uint8_t>(v));
}

// The difference of two int32 values, zigzag-coded (small either way: few bytes).
std::uint64_t zigzag(std::int32_t now, std::int32_t before) {
  const std::int64_t d = static_cast<std::int64_t>(now) - before;
  return (static_cast<std::uint64_t>(d) << 1) ^ static_cast<std::uint64_t>(d >> 63);
}

std::int32_t unzigzag(std::int32_t before, std::uint64_t z) {
  const std::int64_t d = static_cast<std::int64_t>(z >> 1) ^ -static_cast<std::int64_t>(z & 1);
  return static_cast<std::int32_t>(before + d);
}

}  // namespace

void Scope::encode(std::deque<std::uint8_t>& out, const ScopeSample& prev, const Run& run) {
  const ScopeSample& s = run.sample;
  const std::uint8_t mask = static_cast<std::uint8_t>(
      (s.pos != prev.pos ? k_pos : 0) | (s.vel != prev.vel ? k_vel : 0) | (s.cur != prev.cur ? k_cur : 0) |
      (s.target != prev.target ? k_target : 0) | (s.sw != prev.sw ? k_sw : 0) | (run.count != 1 ? k_count : 0));
  out.push_back(mask);
  if (mask & k_pos) put_varint(out, zigzag(s.pos, prev.pos));
  if (mask & k_vel) put_varint(out, zigzag(s.vel, prev.vel));
  if (mask & k_cur) put_varint(out, zigzag(s.cur, prev.cur));
  if (mask & k_target) put_varint(out, zigzag(s.target, prev.target));
  if (mask & k_sw) put_varint(out, s.sw);
  if (mask & k_count) put_varint(out, run.count);
}

Scope::Run Scope::Reader::next() {
  const auto start = at;
  const auto varint = [this] {
    std::uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t b = *at++;
      v |= static_cast<std::uint64_t>(b & 0x7F) << shift;
      if (!(b & 0x80)) return v;
    }
  };
  const std::uint8_t mask = *at++;
  Run r{prev, 1};
  if (mask & k_pos) r.sample.pos = unzigzag(prev.pos, varint());
  if (mask & k_vel) r.sample.vel = unzigzag(prev.vel, varint());
  if (mask & k_cur) r.sample.cur = unzigzag(prev.cur, varint());
  if (mask & k_target) r.sample.target = unzigzag(prev.target, varint());
  if (mask & k_sw) r.sample.sw = static_cast<std::uint16_t>(varint());
  if (mask & k_count) r.count = static_cast<std::uint32_t>(varint());
  prev = r.sample;
  bytes = static_cast<std::size_t>(at - start);
  return r;
}

void Scope::push_run(const ScopeSample& s, std::uint32_t n) {
  if (newest_ && newest_->sample == s) {
    newest_->count += n;
    return;
  }
  if (newest_) {
    encode(bytes_, last_encoded_, *newest_);
    last_encoded_ = newest_->sample;
  }
  newest_ = Run{s, n};
}

// Takes the n oldest samples out of the ring (n < total_).
void Scope::drop_oldest(std::size_t n) {
  while (n > 0) {
    if (bytes_.empty()) {  // only the newest run is left: its start moves, and a read's cursor with it
      newest_->count -= static_cast<std::uint32_t>(n);
      cursor_.reset();
      dropped_ += n;
      total_ -= n;
      first_ms_ += n * k_sample_ms;
      return;
    }
    Reader r{bytes_.begin(), base_};
    const Run oldest = r.next();
    const std::size_t drop = std::min<std::size_t>(oldest.count - oldest_dropped_, n);
    oldest_dropped_ += static_cast<std::uint32_t>(drop);
    dropped_ += drop;
    total_ -= drop;
    first_ms_ += drop * k_sample_ms;
    n -= drop;
    if (oldest_dropped_ == oldest.count) {
      bytes_.erase(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(r.bytes));
      erased_ += r.bytes;
      base_ = oldest.sample;
      oldest_dropped_ = 0;
    }
  }
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
    bytes_.clear();
    base_ = ScopeSample{};
    last_encoded_ = ScopeSample{};
    oldest_dropped_ = 0;
    dropped_ = 0;
    erased_ = 0;
    cursor_.reset();
    newest_.reset();
    total_ = 0;
    first_ms_ = time_ms;
    if (time_ms < next_new_ms_) next_new_ms_ = time_ms;
  }
  push_run(s, static_cast<std::uint32_t>(count));  // ≤ k_capacity (above)
  total_ += static_cast<std::size_t>(count);
  if (total_ > k_capacity) drop_oldest(total_ - k_capacity);
}

ScopeBlock Scope::block_from(std::size_t first) const {
  ScopeBlock b;
  b.sample_ms = k_sample_ms;
  b.t0 = total_ == 0 ? 0 : time_of(first);  // an empty block: the time of the next sample
  if (first >= total_) return b;
  b.samples.reserve(total_ - first);
  const std::uint64_t want = dropped_ + first;  // the first sample wanted
  // Begin at the oldest run, or where the last read began when that run is still held and not
  // after the first sample wanted.
  std::uint64_t run_start = dropped_ - oldest_dropped_;
  std::uint64_t byte = erased_;
  ScopeSample prev = base_;
  if (cursor_ && cursor_->byte >= erased_ && cursor_->run_start <= want) {
    run_start = cursor_->run_start;
    byte = cursor_->byte;
    prev = cursor_->prev;
  }
  const auto take = [&](const ScopeSample& sample, std::uint64_t count) {
    const std::uint64_t end = run_start + count;
    if (end > want) {
      if (b.samples.empty()) cursor_ = Cursor{run_start, byte, prev};
      b.samples.insert(b.samples.end(), static_cast<std::size_t>(end - std::max(run_start, want)), sample);
    }
    run_start = end;
  };
  Reader r{bytes_.begin() + static_cast<std::ptrdiff_t>(byte - erased_), prev};
  while (r.at != bytes_.end()) {
    const Run run = r.next();
    take(run.sample, run.count);
    prev = run.sample;
    byte += r.bytes;
  }
  if (newest_) take(newest_->sample, newest_->count);
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
