// Helpers for the producer of the CANopen observations (the bundle's CAN bus and dictionary write
// tap): they read the few communication objects a classification needs from the dictionary, so
// that wiring the lint is one call per frame or write. Read-only; no hooks, no state.
#pragma once

#include <cstdint>
#include <optional>

#include "drive/od/dictionary.hpp"
#include "lint/observations.hpp"

namespace mcemu::lint {

// A client frame (11-bit identifier `id`) to node `node_id`, classified for the lint: NMT (DLC 2,
// this node or all), SYNC (0x080), SDO request (0x600 + node-id, DLC 8), guarding RTR (0x700 +
// node-id), RPDO (the CAN-ID of a valid 1400h–1403h.01; `motion` when its 1600h–1603h mapping holds
// 6040h, 607Ah or 60FFh; `life_time_ms` = 100Ch × 100Dh while 1017h = 0), else other.
CanRequest classify_can_frame(const od::ObjectDictionary& od, Ms time, Conn conn, std::uint32_t id, bool rtr,
                              std::uint8_t dlc, const std::uint8_t* data, std::uint8_t node_id);

// For a write to a mapping object (1600h–17FFh, 1A00h–1BFFh): the observation, with the validity
// of its PDO's COB-ID (communication object = mapping index − 200h, sub 01h); nullopt otherwise.
std::optional<PdoMappingWrite> pdo_mapping_write(const od::ObjectDictionary& od, const OdWrite& w);

}  // namespace mcemu::lint
