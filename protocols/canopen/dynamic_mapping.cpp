#include "protocols/canopen/dynamic_mapping.hpp"

#include <algorithm>
#include <array>
#include <set>

#include "protocols/canopen/od_access.hpp"
#include "protocols/canopen/pdo_map.hpp"

namespace mcemu::canopen {
namespace {

constexpr std::uint16_t k_rpdo_map = 0x1600;
constexpr std::uint16_t k_tpdo_map = 0x1A00;

bool is_tpdo_map(std::uint16_t index) { return index >= k_tpdo_map; }
std::uint16_t comm_of(std::uint16_t map_index) { return static_cast<std::uint16_t>(map_index - 0x200); }

// §9.7: the objects each direction may map (XDD PDO flags; `optional` = both; 607Ah as RPDO3 maps it).
const std::set<std::uint16_t>& mappable(bool tpdo) {
  static const std::set<std::uint16_t> rpdo = {0x6040, 0x6060, 0x607A, 0x60FF, 0x606D, 0x606E, 0x606F, 0x6070};
  static const std::set<std::uint16_t> t = {0x6041, 0x6061, 0x6064, 0x606C, 0x6402, 0x6406,
                                            0x6407, 0x606D, 0x606E, 0x606F, 0x6070};
  return tpdo ? t : rpdo;
}

// Dummy entries 0002h…0007h: INTEGER8/16/32, UNSIGNED8/16/32.
int dummy_bits(std::uint16_t index) {
  switch (index) {
    case 0x0002:
    case 0x0005: return 8;
    case 0x0003:
    case 0x0006: return 16;
    case 0x0004:
    case 0x0007: return 32;
    default: return 0;
  }
}

bool valid_entry(const od::ObjectDictionary& od, bool tpdo, std::uint32_t raw) {
  const MapEntry e = MapEntry::decode(raw);
  if (e.dummy()) return e.sub == 0 && e.bits == dummy_bits(e.index);
  if (mappable(tpdo).count(e.index) == 0) return false;
  const od::EntryInfo* info = od.info(e.index, e.sub);
  if (info == nullptr || od::is_string(info->type)) return false;
  return e.bits == 8 * od::size_of(info->type);
}

bool pdo_valid(const od::ObjectDictionary& od, std::uint16_t map_index) {
  const auto cob = stored_number(od, comm_of(map_index), 1);
  return cob && (*cob & k_cob_invalid) == 0;
}

}  // namespace

// "mapping entry 0" … "8": names of generated entries have the process's storage (names are views).
constexpr std::array<const char*, 9> k_mapping_names = {"mapping entry 0", "mapping entry 1", "mapping entry 2",
                                                        "mapping entry 3", "mapping entry 4", "mapping entry 5",
                                                        "mapping entry 6", "mapping entry 7", "mapping entry 8"};

void make_mapping_dynamic(std::vector<od::EntryInfo>& entries) {
  for (std::uint16_t base : {k_rpdo_map, k_tpdo_map}) {
    for (std::uint16_t index = base; index < base + 4; ++index) {
      const auto head = std::find_if(entries.begin(), entries.end(),
                                     [&](const od::EntryInfo& e) { return e.index == index && e.sub == 0; });
      if (head == entries.end()) continue;
      od::EntryInfo proto = *head;
      for (std::uint8_t sub = 0; sub <= 8; ++sub) {
        auto it = std::find_if(entries.begin(), entries.end(),
                               [&](const od::EntryInfo& e) { return e.index == index && e.sub == sub; });
        if (it == entries.end()) {
          od::EntryInfo e = proto;
          e.sub = sub;
          e.type = od::DataType::unsigned32;
          e.name = k_mapping_names[sub];
          e.factory = od::Value{std::int64_t{0}};
          e.from_xdd = false;
          entries.push_back(std::move(e));
          it = std::prev(entries.end());
        }
        it->access = od::Access::rw;
        it->cls = od::EntryClass::comm;
        it->pdo = od::PdoFlag::no;
        if (sub == 0) {
          it->validator = [](const od::ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
            return v <= 8 ? od::AbortCode::none : od::AbortCode::invalid_value;
          };
        }
      }
    }
  }
}

DynamicMapping::DynamicMapping(od::ObjectDictionary& od) : od_(od) {
  for (std::uint16_t base : {k_rpdo_map, k_tpdo_map}) {
    for (std::uint16_t index = base; index < base + 4; ++index) {
      if (!od_.find(index, 0)) continue;
      const bool tpdo = is_tpdo_map(index);
      od_.on_write(index, 0, [this, index, tpdo](od::WriteRequest& req) {
        if (pdo_valid(od_, index)) return od::AbortCode::invalid_value;
        const auto count = std::get<std::int64_t>(req.value);
        std::size_t bits = 0;
        for (std::int64_t s = 1; s <= count; ++s) {
          const auto raw = static_cast<std::uint32_t>(stored_number_or(od_, index, static_cast<std::uint8_t>(s), 0));
          if (raw == 0 || !valid_entry(od_, tpdo, raw)) return od::AbortCode::not_mappable;
          bits += raw & 0xFF;
        }
        return bits > 64 ? od::AbortCode::pdo_length : od::AbortCode::none;
      });
      for (std::uint8_t sub = 1; sub <= 8; ++sub) {
        if (!od_.find(index, sub)) continue;
        od_.on_write(index, sub, [this, index, tpdo](od::WriteRequest& req) {
          if (pdo_valid(od_, index) || stored_number_or(od_, index, 0, 0) != 0) return od::AbortCode::invalid_value;
          const auto raw = static_cast<std::uint32_t>(std::get<std::int64_t>(req.value));
          if (raw != 0 && !valid_entry(od_, tpdo, raw)) return od::AbortCode::not_mappable;
          return od::AbortCode::none;
        });
      }
      // COB-ID rule 4 (§9.2): no enabling while the mapping is empty.
      const auto comm = comm_of(index);
      if (od_.find(comm, 1)) {
        od_.on_write(comm, 1, [this, index](od::WriteRequest& req) {
          const auto v = std::get<std::int64_t>(req.value);
          if ((v & k_cob_invalid) == 0 && stored_number_or(od_, index, 0, 0) == 0) return od::AbortCode::invalid_value;
          return od::AbortCode::none;
        });
      }
    }
  }
}

DynamicMapping::~DynamicMapping() {
  for (std::uint16_t base : {k_rpdo_map, k_tpdo_map}) {
    for (std::uint16_t index = base; index < base + 4; ++index) {
      for (std::uint8_t sub = 0; sub <= 8; ++sub) {
        if (od_.find(index, sub)) od_.on_write(index, sub, {});
      }
      if (od_.find(comm_of(index), 1)) od_.on_write(comm_of(index), 1, {});
    }
  }
}

}  // namespace mcemu::canopen
