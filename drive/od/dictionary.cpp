#include "drive/od/dictionary.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace mcemu::od {
namespace {

bool same(const Value& a, const Value& b) { return a == b; }

std::int64_t number_of(const Value& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}
constexpr std::uint32_t key_of(std::uint16_t index, std::uint8_t sub) { return std::uint32_t{index} << 8 | sub; }
// Fibonacci hashing of a key onto a slot of a power-of-two table.
constexpr std::size_t slot_of(std::uint32_t key, std::size_t mask) {
  return static_cast<std::size_t>((std::uint64_t{key} * 0x9E3779B97F4A7C15ull) >> 40) & mask;
}

std::int64_t decode_le(std::span<const std::byte> data, DataType type) {
  const std::size_t n = size_of(type);
  std::uint64_t raw = 0;
  for (std::size_t i = 0; i < n; ++i) {
    raw |= static_cast<std::uint64_t>(std::to_integer<std::uint8_t>(data[i])) << (8 * i);
  }
  if (is_signed(type)) {
    const unsigned bits = static_cast<unsigned>(n * 8);
    const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
    return static_cast<std::int64_t>((raw ^ sign)) - static_cast<std::int64_t>(sign);
  }
  return static_cast<std::int64_t>(raw);
}

// One owner per entry (architecture.md): a second hook would silently replace the first.
std::string hook_conflict(const char* kind, std::uint16_t index, std::uint8_t sub) {
  char where[16];
  std::snprintf(where, sizeof where, "%04Xh.%02Xh", index, sub);
  return std::string("a second ") + kind + " hook for " + where;
}

// A number as an entry of a numeric `type` stores it (§3.2): in range, or a negative 32-bit
// pattern for unsigned32.
Result<std::int64_t> convert_number(DataType type, std::int64_t n) {
  const Range r = type_range(type);
  if (n >= r.min && n <= r.max) return n;
  if (type == DataType::unsigned32 && n >= -2147483648LL && n <= -1) return n + 4294967296LL;
  return n > r.max ? AbortCode::value_too_high : AbortCode::value_too_low;
}
}  // namespace

Result<Value> convert_for_write(const EntryInfo& info, const Value& v) {
  const bool want_string = is_string(info.type);
  if (std::holds_alternative<std::string>(v) != want_string) return AbortCode::type_mismatch;
  if (want_string) return v;
  const auto n = convert_number(info.type, std::get<std::int64_t>(v));
  if (!n) return n.error();
  return Value{*n};
}

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

ObjectDictionary::ObjectDictionary(std::vector<EntryInfo> entries) {
  sort_entries(entries);  // the builders sort already: then this is one pass (issue 26)
  entries_.reserve(entries.size());
  for (auto& info : entries) {
    Value v = info.factory;
    entries_.push_back(Entry{std::move(info), std::move(v)});
  }
  build_index();
  install_error_history_rule();
}

// 1003h.00 (object-dictionary.md §2.4, §5): from outside only 0 may be written, and it clears the
// history. The drive core writes the count itself (origin internal) when it records an error.
void ObjectDictionary::install_error_history_rule() {
  if (!find(0x1003, 0)) return;
  on_write(0x1003, 0, [this](WriteRequest& req) {
    const auto n = std::get<std::int64_t>(req.value);
    if (req.origin == Origin::internal) return AbortCode::none;
    if (n != 0) return AbortCode::invalid_value;
    for (std::uint8_t s = 1; s <= 4; ++s) {
      if (auto h = find(0x1003, s)) set(*h, Value{std::int64_t{0}});
    }
    return AbortCode::none;
  });
}

void ObjectDictionary::build_index() {
  objects_.clear();
  numbers_.resize(entries_.size());
  keys_.resize(entries_.size());
  types_.resize(entries_.size());
  plain_.resize(entries_.size());
  for (std::uint32_t i = 0; i < entries_.size(); ++i) {
    const auto& e = entries_[i].info;
    numbers_[i] = number_of(entries_[i].value);
    keys_[i] = key_of(e.index, e.sub);
    types_[i] = e.type;
    plain_[i] = is_plain(entries_[i]);
    if (i > 0 && entries_[i - 1].info.index == e.index) {
      if (entries_[i - 1].info.sub == e.sub) throw std::logic_error("duplicate OD entry");
      ++objects_.back().count;
    } else {
      objects_.push_back({e.index, i, 1});
    }
  }
  if (entries_.size() >= 0xFFFF) throw std::logic_error("too many OD entries for the slot table");
  std::size_t size = 16;
  while (size < 2 * entries_.size()) size *= 2;
  slots_.assign(size, 0);
  for (std::uint32_t h = 0; h < keys_.size(); ++h) {
    std::size_t i = slot_of(keys_[h], size - 1);
    while (slots_[i] != 0) i = (i + 1) & (size - 1);
    slots_[i] = static_cast<std::uint16_t>(h + 1);
  }
}

Result<Handle> ObjectDictionary::locate(std::uint16_t index, std::uint8_t sub) const {
  const std::uint32_t key = key_of(index, sub);
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = slot_of(key, mask); slots_[i] != 0; i = (i + 1) & mask) {
    const Handle h = slots_[i] - 1u;
    if (keys_[h] == key) return h;
  }
  return has_object(index) ? AbortCode::no_sub : AbortCode::no_object;
}

std::optional<Handle> ObjectDictionary::find(std::uint16_t index, std::uint8_t sub) const {
  auto r = locate(index, sub);
  if (!r) return std::nullopt;
  return *r;
}

Handle ObjectDictionary::handle(std::uint16_t index, std::uint8_t sub) const {
  auto r = locate(index, sub);
  if (!r)
    throw std::out_of_range("object dictionary has no entry " + std::to_string(index) + "." + std::to_string(sub));
  return *r;
}

bool ObjectDictionary::has_object(std::uint16_t index) const {
  auto it = std::lower_bound(objects_.begin(), objects_.end(), index,
                             [](const ObjectSlot& s, std::uint16_t i) { return s.index < i; });
  return it != objects_.end() && it->index == index;
}

const EntryInfo* ObjectDictionary::info(std::uint16_t index, std::uint8_t sub) const {
  auto r = locate(index, sub);
  return r ? &entries_[*r].info : nullptr;
}

Result<Value> ObjectDictionary::read_entry(const Entry& e) const {
  if (e.read_hook == 0 || !read_hooks_[e.read_hook - 1u]) return e.value;
  auto r = read_hooks_[e.read_hook - 1u](e.info);
  if (!r) return AbortCode::general;
  return r;
}

AbortCode ObjectDictionary::check_upload(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  if (entries_[*h].info.access == Access::wo) return AbortCode::write_only;
  return AbortCode::none;
}

Result<Value> ObjectDictionary::read(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const Entry& e = entries_[*h];
  if (e.info.access == Access::wo) return AbortCode::write_only;
  return read_entry(e);
}

Result<std::int64_t> ObjectDictionary::read_number(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const Entry& e = entries_[*h];
  if (e.info.access == Access::wo) return AbortCode::write_only;
  if (is_string(e.info.type)) return AbortCode::type_mismatch;
  auto v = read_entry(e);
  if (!v) return v.error();
  return std::get<std::int64_t>(*v);
}

Result<std::vector<std::byte>> ObjectDictionary::read_bytes(std::uint16_t index, std::uint8_t sub) const {
  auto v = read(index, sub);
  if (!v) return v.error();
  const EntryInfo& inf = *info(index, sub);
  std::vector<std::byte> out;
  if (is_string(inf.type)) {
    const auto& s = std::get<std::string>(*v);
    out.reserve(s.size());
    for (char c : s) out.push_back(static_cast<std::byte>(c));
    return out;
  }
  const auto raw = static_cast<std::uint64_t>(std::get<std::int64_t>(*v));
  for (std::size_t i = 0; i < size_of(inf.type); ++i) out.push_back(static_cast<std::byte>((raw >> (8 * i)) & 0xFF));
  return out;
}

AbortCode ObjectDictionary::check_limits(const Entry& e, std::int64_t v, bool bulk) const {
  if (e.info.limits) {
    if (v > e.info.limits->max) return AbortCode::value_too_high;
    if (v < e.info.limits->min) return AbortCode::value_too_low;
  }
  if (e.info.validator) {
    std::optional<std::int64_t> stored;
    if (!bulk && std::holds_alternative<std::int64_t>(e.value)) stored = std::get<std::int64_t>(e.value);
    return e.info.validator(*this, stored, v);
  }
  return AbortCode::none;
}

void ObjectDictionary::store(Entry& e, Value v) {
  if (same(e.value, v)) return;
  e.value = std::move(v);
  numbers_[static_cast<std::size_t>(&e - entries_.data())] = number_of(e.value);
  ++generation_;
  for (const auto& l : listeners_) l(e.info, e.value);
}

AbortCode ObjectDictionary::commit(Handle h, Value v, Origin origin, Done& done) {
  Entry& e = entries_[h];
  if (std::holds_alternative<std::int64_t>(v)) {
    if (auto c = check_limits(e, std::get<std::int64_t>(v), false); c != AbortCode::none) return c;
  }
  if (e.write_hook == 0 || !write_hooks_[e.write_hook - 1u]) {
    store(e, std::move(v));
    return AbortCode::none;
  }
  WriteRequest req{e.info, origin, e.value, std::move(v), &done};
  const AbortCode c = write_hooks_[e.write_hook - 1u](req);
  if (c != AbortCode::none) return c;
  // The hook may have written other entries (never this vector's layout), so re-index.
  Entry& again = entries_[h];
  auto stored = convert_for_write(again.info, req.value);
  if (!stored) return AbortCode::general;  // a hook produced a value the entry cannot hold: a bug
  store(again, std::move(*stored));
  return AbortCode::none;
}

AbortCode ObjectDictionary::write(std::uint16_t index, std::uint8_t sub, const Value& value, Origin origin, Done done) {
  const AbortCode r = write_value(index, sub, value, origin, done);
  if (tap_) {
    std::int64_t n = std::holds_alternative<std::int64_t>(value) ? std::get<std::int64_t>(value) : 0;
    if (const auto* i = info(index, sub); i && n < 0 && i->type == DataType::unsigned32) n += 4294967296LL;
    tap_(WriteNote{index, sub, n, origin, r, helper_depth_ > 0});
  }
  return r;
}

AbortCode ObjectDictionary::write_value(std::uint16_t index, std::uint8_t sub, const Value& value, Origin origin,
                                        Done& done) {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const Entry& e = entries_[*h];
  if (origin != Origin::internal && (e.info.access == Access::ro || e.info.access == Access::const_)) {
    return AbortCode::read_only;
  }
  auto v = convert_for_write(e.info, value);
  if (!v) return v.error();
  return commit(*h, std::move(*v), origin, done);
}

AbortCode ObjectDictionary::set(Handle h, const Value& value) {
  // The drive's own writes of its actual values, every step: for a plain entry (a number without
  // limits, validator or write hook) the compact arrays decide, and an unchanged value touches no
  // Entry (issue 26: a fleet's drives evict each other's cache lines).
  if (plain_[h] && std::holds_alternative<std::int64_t>(value)) {
    const auto n = convert_number(types_[h], std::get<std::int64_t>(value));
    if (!n) return n.error();
    if (*n == numbers_[h]) return AbortCode::none;
    store(entries_[h], Value{*n});
    return AbortCode::none;
  }
  auto v = convert_for_write(entries_[h].info, value);
  if (!v) return v.error();
  Done none;
  return commit(h, std::move(*v), Origin::internal, none);
}

AbortCode ObjectDictionary::check_download(std::uint16_t index, std::uint8_t sub,
                                           std::optional<std::size_t> size) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const Entry& e = entries_[*h];
  if (e.info.access == Access::ro || e.info.access == Access::const_) return AbortCode::read_only;
  if (size && !is_string(e.info.type)) {
    const std::size_t n = size_of(e.info.type);
    if (*size > n && !(e.info.length_tolerant && *size == 4)) return AbortCode::length_too_high;
    if (*size < n) return AbortCode::length_too_low;
  }
  return AbortCode::none;
}

AbortCode ObjectDictionary::write_bytes(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data,
                                        SdoLength length, Origin origin, Done done) {
  const AbortCode r = write_data(index, sub, data, length, origin, done);
  if (tap_) tap_(WriteNote{index, sub, number_in(index, sub, data), origin, r, helper_depth_ > 0});
  return r;
}

std::int64_t ObjectDictionary::number_in(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data) const {
  const auto* i = info(index, sub);
  if (!i || is_string(i->type)) return 0;
  const std::size_t n = size_of(i->type);
  if (data.size() >= 4 && n < 4 && i->length_tolerant) return decode_le(data.first(4), DataType::integer32);
  return data.size() >= n ? decode_le(data.first(n), i->type) : 0;
}

AbortCode ObjectDictionary::write_data(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data,
                                       SdoLength length, Origin origin, Done& done) {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const Entry& e = entries_[*h];
  if (origin != Origin::internal && (e.info.access == Access::ro || e.info.access == Access::const_)) {
    return AbortCode::read_only;
  }
  if (is_string(e.info.type)) {
    std::string s;
    s.reserve(data.size());
    for (auto b : data) s.push_back(static_cast<char>(b));
    return commit(*h, Value{std::move(s)}, origin, done);
  }
  const std::size_t n = size_of(e.info.type);
  const std::size_t got = data.size();
  if (length == SdoLength::segmented_unindicated && got != n) return AbortCode::type_mismatch;
  if (length == SdoLength::indicated && got > n) {
    if (!(e.info.length_tolerant && got == 4)) return AbortCode::length_too_high;
    const std::int64_t v = decode_le(data, DataType::integer32);
    if (v > 65535) return AbortCode::value_too_high;
    if (v < 0) return AbortCode::value_too_low;
    return commit(*h, Value{v}, origin, done);
  }
  if (got < n) return AbortCode::length_too_low;
  return commit(*h, Value{decode_le(data.first(n), e.info.type)}, origin, done);
}

namespace {
// Registers `hook` at the entry's position in `hooks` (1-based in `slot`), or clears it.
template <class Hook>
void set_hook(std::deque<Hook>& hooks, std::uint16_t& slot, Hook hook, const char* kind, std::uint16_t index,
              std::uint8_t sub) {
  if (slot != 0 && hooks[slot - 1u] && hook) throw std::logic_error(hook_conflict(kind, index, sub));
  if (slot != 0) {
    hooks[slot - 1u] = std::move(hook);
    return;
  }
  if (!hook) return;
  if (hooks.size() >= 0xFFFF) throw std::logic_error("too many OD hooks");
  hooks.push_back(std::move(hook));
  slot = static_cast<std::uint16_t>(hooks.size());
}
}  // namespace

void ObjectDictionary::on_write(std::uint16_t index, std::uint8_t sub, WriteHook hook) {
  const Handle h = handle(index, sub);
  set_hook(write_hooks_, entries_[h].write_hook, std::move(hook), "write", index, sub);
  plain_[h] = is_plain(entries_[h]);
}

bool ObjectDictionary::is_plain(const Entry& e) const {
  const bool hooked = e.write_hook != 0 && write_hooks_[e.write_hook - 1u];
  return !is_string(e.info.type) && !e.info.limits && !e.info.validator && !hooked;
}

void ObjectDictionary::on_read(std::uint16_t index, std::uint8_t sub, ReadHook hook) {
  set_hook(read_hooks_, entries_[handle(index, sub)].read_hook, std::move(hook), "read", index, sub);
}

void ObjectDictionary::on_change(ChangeListener listener) { listeners_.push_back(std::move(listener)); }

std::vector<LoadIssue> ObjectDictionary::load_values(std::span<const StoredValue> values) {
  std::vector<LoadIssue> issues;
  for (const auto& sv : values) {
    auto h = locate(sv.index, sv.sub);
    if (!h) {
      issues.push_back({sv.index, sv.sub, h.error()});
      continue;
    }
    Entry& e = entries_[*h];
    auto v = convert_for_write(e.info, sv.value);
    if (!v) {
      issues.push_back({sv.index, sv.sub, v.error()});
      continue;
    }
    if (std::holds_alternative<std::int64_t>(*v)) {
      if (auto c = check_limits(e, std::get<std::int64_t>(*v), true); c != AbortCode::none) {
        issues.push_back({sv.index, sv.sub, c});
        continue;
      }
    }
    if (!same(e.value, *v)) ++generation_;
    e.value = std::move(*v);
    numbers_[*h] = number_of(e.value);
  }
  return issues;
}

void ObjectDictionary::for_each(const std::function<void(const EntryInfo&, const Value&)>& fn) const {
  for (const auto& e : entries_) fn(e.info, e.value);
}

}  // namespace mcemu::od
