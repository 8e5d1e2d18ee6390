#include "protocols/canopen/comm_reload.hpp"

#include <vector>

#include "protocols/canopen/od_access.hpp"

namespace mcemu::canopen {
namespace {

bool communication_entry(const od::EntryInfo& e) {
  if (e.index == 0x3404 && e.sub == 3) return true;
  if (e.index < 0x1000 || e.index > 0x1FFF) return false;
  return e.cls == od::EntryClass::comm || e.cls == od::EntryClass::param;
}

}  // namespace

void reload_communication_objects(od::ObjectDictionary& od, std::span<const od::StoredValue> factory_image,
                                  std::span<const od::StoredValue> stored) {
  std::vector<od::StoredValue> image;
  od.for_each([&](const od::EntryInfo& e, const od::Value&) {
    if (communication_entry(e)) image.push_back({e.index, e.sub, e.factory});
  });
  // Later values win in a bulk load: preset factory, then the factory image, then the file.
  for (const auto layer : {factory_image, stored}) {
    for (const auto& s : layer) {
      const od::EntryInfo* e = od.info(s.index, s.sub);
      if (e != nullptr && communication_entry(*e)) image.push_back(s);
    }
  }
  (void)od.load_values(image);
}

void apply_node_id(od::ObjectDictionary& od, std::uint8_t old_id, std::uint8_t new_id) {
  struct Cob {
    std::uint16_t index;
    std::uint8_t sub;
    std::uint32_t base;
  };
  static constexpr Cob k_cobs[] = {{0x1014, 0, 0x080}, {0x1200, 1, 0x600}, {0x1200, 2, 0x580}, {0x1400, 1, 0x200},
                                   {0x1401, 1, 0x300}, {0x1402, 1, 0x400}, {0x1403, 1, 0x500}, {0x1800, 1, 0x180},
                                   {0x1801, 1, 0x280}, {0x1802, 1, 0x380}, {0x1803, 1, 0x480}};
  std::vector<od::StoredValue> changes;
  for (const auto& c : k_cobs) {
    const auto v = stored_number(od, c.index, c.sub);
    if (!v) continue;
    const auto raw = static_cast<std::uint32_t>(*v);
    const std::uint32_t id_part = raw & ~(k_cob_invalid | k_cob_no_rtr);
    if (id_part != c.base + old_id && id_part != c.base + k_factory_node_id) continue;
    const std::uint32_t next = (raw & (k_cob_invalid | k_cob_no_rtr)) | (c.base + new_id);
    if (next != raw) changes.push_back({c.index, c.sub, od::Value{static_cast<std::int64_t>(next)}});
  }
  (void)od.load_values(changes);
}

}  // namespace mcemu::canopen
