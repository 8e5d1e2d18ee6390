// The immutable side of an object dictionary (object-dictionary.md §2): its entries in (index, sub)
// order and everything derived from them alone — the key hash, the objects, each entry's type and
// whether it is plain, the factory numbers. A dictionary keeps only its values and hooks; every
// dictionary built from equal presets shares one Layout (preset_layout(), issue 26: a drive built
// in ≤ 50 µs, its fuzz targets at ≥ 1000 inputs per second, and a fleet whose drives share one
// copy of their descriptions instead of evicting each other's). Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "drive/od/abort_code.hpp"
#include "drive/od/types.hpp"

namespace mcemu::model {
struct ModelPreset;
}

namespace mcemu::od {

class ObjectDictionary;

// Extra write rule of an entry beyond its data type (object-dictionary.md §5). Gets the stored
// value (nullopt during a bulk load, where rules about the transition from the stored value do not
// apply) and the new value; returns none or the abort code (0x06090030/31/32). A validator sees
// the dictionary it is asked for: it keeps no state of its own (the layout is shared).
using Validator =
    std::function<AbortCode(const ObjectDictionary&, std::optional<std::int64_t> stored, std::int64_t next)>;

struct EntryInfo {
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::uint8_t object_code = 7;  // 7 VAR, 8 ARRAY, 9 RECORD
  DataType type = DataType::unsigned8;
  Access access = Access::ro;
  PdoFlag pdo = PdoFlag::no;
  EntryClass cls = EntryClass::live;
  // Names are views of storage that lives as long as the process (the generated tables, literals, or
  // static name tables of generated entries): a drive's ~800 entries are built without copying or
  // allocating their names (issue 26: a whole drive in ≤ 50 us).
  std::string_view name;
  std::string_view object_name;
  Value factory;                 // factory value of the preset (before --config)
  std::optional<Range> limits;   // min/max of §5 (.31/.32)
  Validator validator;           // sets and structural rules of §5 (.30)
  bool length_tolerant = false;  // 4-byte SDO writes accepted (object-dictionary.md §3.1)
  bool from_xdd = true;          // false for the mcemu additions of §8.3
};

using Handle = std::uint32_t;

// Flags by handle, as bits in 64-bit words (handle h: bit h % 64 of word h / 64): a dictionary
// copies the layout's in one go and can prefetch them.
class HandleBits {
 public:
  explicit HandleBits(std::size_t n = 0) : words_((n + 63) / 64) {}
  bool operator[](Handle h) const { return (words_[h / 64] >> (h % 64)) & 1u; }
  void set(Handle h, bool on) {
    const std::uint64_t bit = std::uint64_t{1} << (h % 64);
    words_[h / 64] = on ? words_[h / 64] | bit : words_[h / 64] & ~bit;
  }
  void set_all() { words_.assign(words_.size(), ~std::uint64_t{0}); }
  void prefetch() const {
    for (std::size_t i = 0; i < words_.size(); i += 8) __builtin_prefetch(&words_[i]);
  }

 private:
  std::vector<std::uint64_t> words_;
};

class Layout {
 public:
  // Sorts the entries by (index, sub) and indexes them; throws std::logic_error for a duplicate.
  explicit Layout(std::vector<EntryInfo> entries);
  Layout(const Layout&) = delete;
  Layout& operator=(const Layout&) = delete;

  std::size_t size() const { return entries_.size(); }
  const EntryInfo& info(Handle h) const { return entries_[h]; }
  // Checks 1–2 of §4.1: the handle, or no_object / no_sub.
  Result<Handle> locate(std::uint16_t index, std::uint8_t sub) const;
  bool has_object(std::uint16_t index) const;

  DataType type(Handle h) const { return types_[h]; }
  // A number without limits or validator: a write of the right type needs no check beyond its range.
  bool unchecked(Handle h) const { return unchecked_[h]; }
  const HandleBits& unchecked_flags() const { return unchecked_; }  // a drive copies them as its plain flags
  // A master can write the entry (rw or wo): a setting, not a value the drive reports.
  bool setting(Handle h) const { return setting_[h]; }
  std::int64_t factory_number(Handle h) const { return factory_numbers_[h]; }
  const std::vector<std::int64_t>& factory_numbers() const { return factory_numbers_; }
  // Position of a string entry among the string entries (the dictionary keeps their values apart);
  // k_no_string for a number.
  static constexpr std::uint16_t k_no_string = 0xFFFF;
  std::uint16_t string_slot(Handle h) const { return string_slots_[h]; }
  const std::vector<Handle>& string_handles() const { return string_handles_; }

 private:
  struct ObjectSlot {
    std::uint16_t index;
    std::uint32_t first;
    std::uint32_t count;
  };

  std::vector<EntryInfo> entries_;
  std::vector<ObjectSlot> objects_;
  // keys_[h] is index << 8 | sub; slots_ is an open-addressing hash of keys_ (handle + 1, 0 = empty,
  // a power of two ≥ 2× the entries): locate() is one or two probes.
  std::vector<std::uint32_t> keys_;
  std::vector<std::uint16_t> slots_;
  std::vector<DataType> types_;
  HandleBits unchecked_;
  std::vector<bool> setting_;
  std::vector<std::int64_t> factory_numbers_;  // 0 for strings
  std::vector<std::uint16_t> string_slots_;
  std::vector<Handle> string_handles_;
};

// Sorts entries by (index, sub) — the order a dictionary keeps — moving each entry once (a sort of
// the entries themselves moves their strings ~n log n times).
void sort_entries(std::vector<EntryInfo>& entries);

// The layout of a preset's dictionary. `variant` tells apart layouts that the caller builds
// differently from the same preset (0 = build_entries(preset) as is). Equal presets (every field,
// model::ModelPreset's operator==) and the same variant give the same Layout while a dictionary of
// it lives, and the last few asked for are kept, so that a fuzz target that builds a drive per
// input builds its layout once. `build` makes the entries when no equal one is known.
// Single-threaded, like every dictionary (design.md: drive/ is pure, no locks): a process builds
// its drives on one thread.
std::shared_ptr<const Layout> preset_layout(const model::ModelPreset& preset, std::uint32_t variant,
                                            const std::function<std::vector<EntryInfo>()>& build);

}  // namespace mcemu::od
