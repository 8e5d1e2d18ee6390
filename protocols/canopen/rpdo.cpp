#include "protocols/canopen/rpdo.hpp"

#include <algorithm>
#include <cstdio>

#include "protocols/canopen/od_access.hpp"
#include "protocols/canopen/pdo_map.hpp"

namespace mcemu::canopen {

bool RpdoSet::on_frame(const can::Frame& frame) {
  if (frame.extended || frame.rtr) return false;
  for (int n = 0; n < 4; ++n) {
    const auto comm = static_cast<std::uint16_t>(0x1400 + n);
    const auto cob = stored_number(od_, comm, 1);
    if (!cob || (*cob & k_cob_invalid) != 0 || static_cast<std::uint32_t>(*cob & 0x7FF) != frame.id) continue;
    const auto map = read_mapping(od_, static_cast<std::uint16_t>(0x1600 + n));
    if (!map) continue;
    State& s = state_[static_cast<std::size_t>(n)];
    const std::size_t need = mapped_bytes(*map);
    if (frame.dlc < need) {
      length_emcy(s, LengthState::too_short);
      return true;
    }
    length_emcy(s, frame.dlc > need ? LengthState::too_long : LengthState::ok);
    std::vector<std::uint8_t> data(frame.data.begin(), frame.data.begin() + frame.dlc);
    const auto type = stored_number_or(od_, comm, 2, 255);
    if (type <= 240) {
      s.buffered = std::move(data);  // a later frame before the SYNC replaces it
    } else {
      apply(n, data);
    }
    return true;
  }
  return false;
}

void RpdoSet::length_emcy(State& s, LengthState next) {
  if (s.length == next) return;
  s.length = next;
  if (!hooks_.emcy) return;
  // Communication EMCYs add the generic and communication bits to 1001h, which they do not change.
  const auto reg = static_cast<std::uint8_t>(od_.read_number(0x1001, 0).ok() ? *od_.read_number(0x1001, 0) : 0);
  switch (next) {
    case LengthState::too_short: hooks_.emcy(0x8210, static_cast<std::uint8_t>(reg | 0x11)); break;
    case LengthState::too_long: hooks_.emcy(0x8220, static_cast<std::uint8_t>(reg | 0x11)); break;
    case LengthState::ok: hooks_.emcy(0x0000, reg); break;
  }
}

void RpdoSet::apply(int n, const std::vector<std::uint8_t>& data) {
  const auto map = read_mapping(od_, static_cast<std::uint16_t>(0x1600 + n));
  if (!map) return;
  struct Item {
    MapEntry entry;
    std::size_t pos;
  };
  std::vector<Item> items;
  std::size_t pos = 0;
  for (const auto& e : *map) {
    const std::size_t len = (e.bits + 7u) / 8u;
    if (pos + len > data.size()) break;
    if (!e.dummy()) items.push_back({e, pos});
    pos += len;
  }
  std::stable_partition(items.begin(), items.end(), [](const Item& i) { return i.entry.index != 0x6040; });
  for (const auto& [e, at] : items) {
    const std::size_t len = (e.bits + 7u) / 8u;
    std::vector<std::byte> bytes(len);
    for (std::size_t i = 0; i < len; ++i) bytes[i] = static_cast<std::byte>(data[at + i]);
    const auto code = od_.write_bytes(e.index, e.sub, bytes, od::SdoLength::indicated, od::Origin::sdo);
    if (hooks_.after_write) hooks_.after_write();
    if (code != od::AbortCode::none && hooks_.diagnostic) {
      char text[96];
      std::snprintf(text, sizeof text, "RPDO%d: write of %04Xh.%02Xh refused with 0x%08X", n + 1, e.index, e.sub,
                    od::to_u32(code));
      hooks_.diagnostic(text);
    }
  }
}

void RpdoSet::on_sync() {
  for (int n = 0; n < 4; ++n) {
    auto& s = state_[static_cast<std::size_t>(n)];
    if (!s.buffered) continue;
    auto data = std::move(*s.buffered);
    s.buffered.reset();
    apply(n, data);
  }
}

void RpdoSet::leave_operational() {
  for (auto& s : state_) s.buffered.reset();
}

void RpdoSet::reset() { state_ = {}; }

}  // namespace mcemu::canopen
