#include "lint/canopen_view.hpp"

namespace mcemu::lint {

namespace {

constexpr std::uint32_t k_invalid = 0x80000000u;

std::optional<std::int64_t> number(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
  const auto h = od.find(index, sub);
  if (!h) return std::nullopt;
  return od.number(*h);
}

bool maps_motion(const od::ObjectDictionary& od, std::uint16_t mapping) {
  const auto n = number(od, mapping, 0);
  if (!n) return false;
  for (std::int64_t s = 1; s <= *n && s <= 8; ++s) {
    const auto e = number(od, mapping, static_cast<std::uint8_t>(s));
    if (!e) continue;
    const auto index = static_cast<std::uint16_t>((static_cast<std::uint32_t>(*e) >> 16) & 0xFFFF);
    if (index == 0x6040 || index == 0x607A || index == 0x60FF) return true;
  }
  return false;
}

std::uint32_t life_time(const od::ObjectDictionary& od) {
  if (number(od, 0x1017, 0).value_or(0) != 0) return 0;  // heartbeat on: no guarding (CiA 301)
  const auto guard = number(od, 0x100C, 0).value_or(0);
  const auto factor = number(od, 0x100D, 0).value_or(0);
  return static_cast<std::uint32_t>(guard * factor);
}

}  // namespace

CanRequest classify_can_frame(const od::ObjectDictionary& od, Ms time, Conn conn, std::uint32_t id, bool rtr,
                              std::uint8_t dlc, const std::uint8_t* data, std::uint8_t node_id) {
  CanRequest r;
  r.time = time;
  r.conn = conn;
  id &= 0x7FF;
  if (id == 0 && !rtr && dlc == 2) {
    if (data[1] == 0 || data[1] == node_id) r.kind = CanKind::nmt;
    return r;
  }
  if (id == 0x080 && !rtr) {
    r.kind = CanKind::sync;
    return r;
  }
  if (id == 0x600u + node_id && !rtr && dlc == 8) {
    r.kind = CanKind::sdo;
    r.byte0 = data[0];
    return r;
  }
  if (id == 0x700u + node_id && rtr) {
    r.kind = CanKind::guarding;
    return r;
  }
  if (rtr) return r;
  for (std::uint16_t k = 0; k < 4; ++k) {
    const auto cob = number(od, static_cast<std::uint16_t>(0x1400 + k), 1);
    if (!cob || (static_cast<std::uint32_t>(*cob) & k_invalid) || (static_cast<std::uint32_t>(*cob) & 0x7FF) != id) {
      continue;
    }
    r.kind = CanKind::rpdo;
    r.rpdo = static_cast<std::uint8_t>(k + 1);
    r.motion = maps_motion(od, static_cast<std::uint16_t>(0x1600 + k));
    r.life_time_ms = life_time(od);
    return r;
  }
  return r;
}

std::optional<PdoMappingWrite> pdo_mapping_write(const od::ObjectDictionary& od, const OdWrite& w) {
  const bool rx = w.index >= 0x1600 && w.index <= 0x17FF;
  const bool tx = w.index >= 0x1A00 && w.index <= 0x1BFF;
  if (!rx && !tx) return std::nullopt;
  const auto cob = number(od, static_cast<std::uint16_t>(w.index - 0x200), 1);
  if (!cob) return std::nullopt;
  PdoMappingWrite m;
  m.time = w.time;
  m.conn = w.conn;
  m.origin = w.origin;
  m.mapping_index = w.index;
  m.sub = w.sub;
  m.pdo_valid = (static_cast<std::uint32_t>(*cob) & k_invalid) == 0;
  m.result = w.result;
  return m;
}

}  // namespace mcemu::lint
