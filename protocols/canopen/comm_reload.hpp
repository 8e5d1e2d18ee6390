// Reloading communication objects and applying a node-id (slcan-canopen.md §4.1, §4.4). Pure.
#pragma once

#include <cstdint>
#include <span>

#include "drive/od/dictionary.hpp"

namespace mcemu::canopen {

constexpr std::uint8_t k_factory_node_id = 50;

// NMT reset communication step 3: the communication parameters (comm and param classes of
// 1000h–1FFFh) and 3404h.03 get their value from the factory image (`factory_image`, e.g. the
// persistence service's image that includes --config; entries it lacks take the preset's factory
// value), then the stored values of those entries from `stored` (persistence.md §5). Bulk load:
// no hooks, no notifications. Live and command entries (1001h, 1002h, 1003h, 1010h, 1011h) are
// left alone.
void reload_communication_objects(od::ObjectDictionary& od, std::span<const od::StoredValue> factory_image = {},
                                  std::span<const od::StoredValue> stored = {});

// Every COB-ID object whose value (bits 31 and 30 ignored) equals its predefined value for
// `old_id` or for the factory node-id 50 gets the predefined value for `new_id`, bits 31/30 kept.
// Covers 1014h, 1200h.01/.02, 1400h–1403h.01, 1800h–1803h.01.
void apply_node_id(od::ObjectDictionary& od, std::uint8_t old_id, std::uint8_t new_id);

}  // namespace mcemu::canopen
