#include "drive/od/layout.hpp"

#include <algorithm>
#include <deque>
#include <stdexcept>

#include "drive/model/model_preset.hpp"

namespace mcemu::od {
namespace {

constexpr std::uint32_t key_of(std::uint16_t index, std::uint8_t sub) { return std::uint32_t{index} << 8 | sub; }
// Fibonacci hashing of a key onto a slot of a power-of-two table.
constexpr std::size_t slot_of(std::uint32_t key, std::size_t mask) {
  return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> 40) & mask;
}

}  // namespace

void sort_entries(std::vector<EntryInfo>& entries) {
  // (index, sub, position) packed in one integer: a plain integer sort, stable by position.
  std::vector<std::uint64_t> order(entries.size());
  bool sorted = true;
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    order[i] = (std::uint64_t{entries[i].index} << 40) | (std::uint64_t{entries[i].sub} << 32) | i;
    if (i > 0 && (order[i] >> 32) < (order[i - 1] >> 32)) sorted = false;
  }
  if (sorted) return;
  std::sort(order.begin(), order.end());
  std::vector<EntryInfo> out;
  out.reserve(entries.size());
  for (const auto key : order) out.push_back(std::move(entries[static_cast<std::uint32_t>(key)]));
  entries.swap(out);
}

Layout::Layout(std::vector<EntryInfo> entries) : entries_(std::move(entries)) {
  sort_entries(entries_);  // the builders sort already: then this is one pass (issue 26)
  const std::size_t n = entries_.size();
  if (n >= 0xFFFF) throw std::logic_error("too many OD entries for the slot table");
  keys_.resize(n);
  types_.resize(n);
  unchecked_ = HandleBits(n);
  setting_.resize(n);
  factory_numbers_.resize(n);
  string_slots_.assign(n, k_no_string);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& e = entries_[i];
    keys_[i] = key_of(e.index, e.sub);
    types_[i] = e.type;
    setting_[i] = e.access == Access::rw || e.access == Access::wo;
    // A factory value of the wrong kind is a builder's bug: stored as it is, it would read back as
    // something its type refuses.
    if (std::holds_alternative<std::string>(e.factory) != is_string(e.type)) {
      throw std::logic_error("OD entry " + std::to_string(e.index) + "." + std::to_string(e.sub) +
                             ": factory value of the wrong kind");
    }
    if (is_string(e.type)) {
      string_slots_[i] = static_cast<std::uint16_t>(string_handles_.size());
      string_handles_.push_back(i);
    } else {
      factory_numbers_[i] = std::get<std::int64_t>(e.factory);
      unchecked_.set(i, !e.limits && !e.validator);
    }
    if (i > 0 && entries_[i - 1].index == e.index) {
      if (entries_[i - 1].sub == e.sub) throw std::logic_error("duplicate OD entry");
      ++objects_.back().count;
    } else {
      objects_.push_back({e.index, i, 1});
    }
  }
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  slots_.assign(size, 0);
  for (std::uint32_t h = 0; h < n; ++h) {
    std::size_t i = slot_of(keys_[h], size - 1);
    while (slots_[i] != 0) i = (i + 1) & (size - 1);
    slots_[i] = static_cast<std::uint16_t>(h + 1);
  }
}

Result<Handle> Layout::locate(std::uint16_t index, std::uint8_t sub) const {
  const std::uint32_t key = key_of(index, sub);
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slot_of(key, mask); slots_[i] != 0; i = (i + 1) & mask) {
    const Handle h = slots_[i] - 1u;
    if (keys_[h] == key) return h;
  }
  return has_object(index) ? AbortCode::no_sub : AbortCode::no_object;
}

bool Layout::has_object(std::uint16_t index) const {
  auto it = std::lower_bound(objects_.begin(), objects_.end(), index,
                             [](const ObjectSlot& s, std::uint16_t i) { return s.index < i; });
  return it != objects_.end() && it->index == index;
}

std::shared_ptr<const Layout> preset_layout(const model::ModelPreset& preset, std::uint32_t variant,
                                            const std::function<std::vector<EntryInfo>()>& build) {
  struct Known {
    model::ModelPreset preset;
    std::uint32_t variant;
    std::weak_ptr<const Layout> layout;
  };
  constexpr std::size_t k_recent = 4;  // kept alive without a dictionary (a fuzz input's drive dies)
  static std::vector<Known> known;     // only layouts that still live
  static std::deque<std::shared_ptr<const Layout>> recent;

  std::shared_ptr<const Layout> found;
  std::erase_if(known, [&](const Known& k) {
    auto alive = k.layout.lock();
    if (!alive) return true;
    if (!found && k.variant == variant && k.preset == preset) found = std::move(alive);
    return false;
  });
  if (!found) {
    found = std::make_shared<const Layout>(build());
    known.push_back({preset, variant, found});
  }
  if (std::find(recent.begin(), recent.end(), found) == recent.end()) {
    recent.push_front(found);
    if (recent.size() > k_recent) recent.pop_back();
  }
  return found;
}

}  // namespace mcemu::od
