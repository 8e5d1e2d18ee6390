#include "protocols/canopen/tpdo.hpp"

#include "protocols/canopen/od_access.hpp"

namespace mcemu::canopen {
namespace {

bool event_driven(int type) { return type == 254 || type == 255; }
bool synchronous(int type) { return type >= 0 && type <= 240; }

}  // namespace

const TpdoSet::Pdo& TpdoSet::pdo(int n) const {
  if (resolved_at_ != od_.settings_generation()) {
    for (int k = 0; k < 4; ++k) {
      Pdo& p = pdos_[static_cast<std::size_t>(k)];
      p = Pdo{};
      const auto comm = static_cast<std::uint16_t>(0x1800 + k);
      const auto mapping = static_cast<std::uint16_t>(0x1A00 + k);
      const auto cob = stored_number(od_, comm, 1);
      if (!cob || !od_.has_object(mapping)) continue;
      Config& c = p.config;
      c.exists = true;
      const auto raw = static_cast<std::uint32_t>(*cob);
      c.valid = (raw & k_cob_invalid) == 0;
      c.rtr_allowed = (raw & k_cob_no_rtr) == 0;
      c.can_id = raw & 0x7FF;
      c.type = static_cast<int>(stored_number_or(od_, comm, 2, 255));
      // 100 µs units; simulated time has 1 ms resolution, so a partial millisecond rounds up.
      c.inhibit = Millis((stored_number_or(od_, comm, 3, 0) + 9) / 10);
      c.event_timer = Millis(stored_number_or(od_, comm, 5, 0));
      if (const auto map = read_mapping(od_, mapping)) p.map = resolve_mapping(od_, *map);
    }
    resolved_at_ = od_.settings_generation();
  }
  return pdos_[static_cast<std::size_t>(n)];
}

void TpdoSet::send(int n, const Config& c, const PdoData& data, Millis now, Outbox& out) {
  out.tpdo.emplace_back(n, make_frame(c.can_id, data.bytes.data(), data.size));
  State& s = state_[static_cast<std::size_t>(n)];
  s.last = data;
  s.last_time = now;
  s.due.reset();
}

void TpdoSet::enter_operational(Millis now, Outbox& out) {
  state_ = {};
  for (int n = 0; n < 4; ++n) {
    const Config& c = config(n);
    if (c.exists && c.valid && event_driven(c.type)) send(n, c, payload(n), now, out);
  }
}

void TpdoSet::leave_operational() { state_ = {}; }

void TpdoSet::on_sync(Millis now, Outbox& out) {
  for (int n = 0; n < 4; ++n) {
    const Config& c = config(n);
    if (!c.exists || !c.valid) continue;
    State& s = state_[static_cast<std::size_t>(n)];
    if (c.type == 0) {
      auto p = payload(n);
      if (!s.last || *s.last != p) send(n, c, p, now, out);
    } else if (synchronous(c.type)) {
      if (++s.sync_count >= c.type) {
        s.sync_count = 0;
        send(n, c, payload(n), now, out);
      }
    } else if (c.type == 252) {
      s.sampled = payload(n);
    }
  }
}

bool TpdoSet::on_rtr(std::uint32_t can_id, Millis now, Outbox& out) {
  for (int n = 0; n < 4; ++n) {
    const Config& c = config(n);
    if (!c.exists || !c.valid || !c.rtr_allowed || c.can_id != can_id) continue;
    State& s = state_[static_cast<std::size_t>(n)];
    send(n, c, (c.type == 252 && s.sampled) ? *s.sampled : payload(n), now, out);
    return true;
  }
  return false;
}

void TpdoSet::check(Millis now, Outbox& out) {
  for (int n = 0; n < 4; ++n) {
    const Config& c = config(n);
    State& s = state_[static_cast<std::size_t>(n)];
    if (!c.exists || !c.valid || !event_driven(c.type)) {
      s.due.reset();
      continue;
    }
    auto p = payload(n);
    const bool changed = !s.last || *s.last != p;
    const bool timer = c.event_timer.count() > 0 && s.last_time && now >= *s.last_time + c.event_timer;
    if (!changed && !timer) {
      s.due.reset();
      continue;
    }
    if (s.last_time && c.inhibit.count() > 0 && now < *s.last_time + c.inhibit) {
      s.due = *s.last_time + c.inhibit;  // sent at the window's end with the values current then
      continue;
    }
    send(n, c, p, now, out);
  }
}

std::optional<Millis> TpdoSet::next_deadline() const {
  std::optional<Millis> best;
  const auto consider = [&](Millis t) {
    if (!best || t < *best) best = t;
  };
  for (int n = 0; n < 4; ++n) {
    const State& s = state_[static_cast<std::size_t>(n)];
    if (s.due) consider(*s.due);
    const Config& c = config(n);
    if (c.exists && c.valid && event_driven(c.type) && c.event_timer.count() > 0 && s.last_time) {
      consider(*s.last_time + c.event_timer);
    }
  }
  return best;
}

}  // namespace mcemu::canopen
