#include "drive/od/dictionary.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace mcemu::od {
namespace {

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

ObjectDictionary::ObjectDictionary(std::shared_ptr<const Layout> layout)
    : layout_(std::move(layout)),
      numbers_(layout_->factory_numbers()),
      hooks_(layout_->size()),
      plain_(layout_->unchecked_flags()),
      watched_(layout_->size()) {
  strings_.reserve(layout_->string_handles().size());
  for (const Handle h : layout_->string_handles()) strings_.push_back(std::get<std::string>(layout_->info(h).factory));
  install_error_history_rule();
}

ObjectDictionary::ObjectDictionary(std::vector<EntryInfo> entries)
    : ObjectDictionary(std::make_shared<const Layout>(std::move(entries))) {}

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

bool ObjectDictionary::has_object(std::uint16_t index) const { return layout_->has_object(index); }

const EntryInfo* ObjectDictionary::info(std::uint16_t index, std::uint8_t sub) const {
  auto r = locate(index, sub);
  return r ? &layout_->info(*r) : nullptr;
}

Value ObjectDictionary::value(Handle h) const {
  const auto slot = layout_->string_slot(h);
  return slot == Layout::k_no_string ? Value{numbers_[h]} : Value{strings_[slot]};
}

Result<Value> ObjectDictionary::read_entry(Handle h) const {
  const auto hook = hooks_[h].read;
  if (hook == 0 || !read_hooks_[hook - 1u]) return value(h);
  auto r = read_hooks_[hook - 1u](layout_->info(h));
  if (!r) return AbortCode::general;
  return r;
}

AbortCode ObjectDictionary::check_upload(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  if (layout_->info(*h).access == Access::wo) return AbortCode::write_only;
  return AbortCode::none;
}

Result<Value> ObjectDictionary::read(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  return read(*h);
}

Result<Value> ObjectDictionary::read(Handle h) const {
  if (layout_->info(h).access == Access::wo) return AbortCode::write_only;
  return read_entry(h);
}

Result<std::int64_t> ObjectDictionary::read_number(std::uint16_t index, std::uint8_t sub) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const EntryInfo& info = layout_->info(*h);
  if (info.access == Access::wo) return AbortCode::write_only;
  if (is_string(info.type)) return AbortCode::type_mismatch;
  auto v = read_entry(*h);
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

AbortCode ObjectDictionary::check_limits(Handle h, std::int64_t v, bool bulk) const {
  const EntryInfo& info = layout_->info(h);
  if (info.limits) {
    if (v > info.limits->max) return AbortCode::value_too_high;
    if (v < info.limits->min) return AbortCode::value_too_low;
  }
  if (info.validator) {
    std::optional<std::int64_t> stored;
    if (!bulk && !is_string(info.type)) stored = numbers_[h];
    return info.validator(*this, stored, v);
  }
  return AbortCode::none;
}

void ObjectDictionary::store(Handle h, Value v) {
  const auto slot = layout_->string_slot(h);
  if (slot == Layout::k_no_string) {
    const auto n = std::get<std::int64_t>(v);
    if (numbers_[h] == n) return;
    numbers_[h] = n;
  } else {
    auto& s = std::get<std::string>(v);
    if (strings_[slot] == s) return;
    strings_[slot] = std::move(s);
  }
  ++generation_;
  if (layout_->setting(h)) ++settings_generation_;
  if (!watched_[h]) return;
  const Value now = value(h);
  for (std::size_t i = 0; i < listeners_.size(); ++i) {  // a listener may register another
    if (listeners_[i].entries.empty() || listeners_[i].entries[h]) listeners_[i].fn(layout_->info(h), now);
  }
}

AbortCode ObjectDictionary::commit(Handle h, Value v, Origin origin, Done& done) {
  if (std::holds_alternative<std::int64_t>(v)) {
    if (auto c = check_limits(h, std::get<std::int64_t>(v), false); c != AbortCode::none) return c;
  }
  if (!hooked_write(h)) {
    store(h, std::move(v));
    return AbortCode::none;
  }
  const Value stored = value(h);
  WriteRequest req{layout_->info(h), origin, stored, std::move(v), &done};
  const AbortCode c = write_hooks_[hooks_[h].write - 1u](req);
  if (c != AbortCode::none) return c;
  auto converted = convert_for_write(layout_->info(h), req.value);
  if (!converted) return AbortCode::general;  // a hook produced a value the entry cannot hold: a bug
  store(h, std::move(*converted));
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
  const EntryInfo& info = layout_->info(*h);
  if (origin != Origin::internal && (info.access == Access::ro || info.access == Access::const_)) {
    return AbortCode::read_only;
  }
  auto v = convert_for_write(info, value);
  if (!v) return v.error();
  return commit(*h, std::move(*v), origin, done);
}

// The cache line of numbers_[h], counted from the line numbers_ starts in.
std::size_t ObjectDictionary::number_line(Handle h) const {
  return (reinterpret_cast<std::uintptr_t>(&numbers_[h]) >> 6) -
         (reinterpret_cast<std::uintptr_t>(numbers_.data()) >> 6);
}

void ObjectDictionary::prefetch() const {
  const auto base = reinterpret_cast<std::uintptr_t>(numbers_.data()) & ~std::uintptr_t{63};
  for (std::size_t w = 0; w < set_lines_.size(); ++w) {
    for (std::uint64_t bits = set_lines_[w]; bits != 0; bits &= bits - 1) {
      __builtin_prefetch(
          reinterpret_cast<const void*>(base + 64 * (64 * w + static_cast<std::size_t>(__builtin_ctzll(bits)))));
    }
  }
  plain_.prefetch();
  watched_.prefetch();
}

AbortCode ObjectDictionary::set(Handle h, const Value& value) {
  // The drive's own writes of its actual values, every step: for a plain entry (a number without
  // limits, validator or write hook) the compact arrays decide, and an unchanged value touches no
  // entry (issue 26: a fleet's drives evict each other's cache lines).
  if (const std::size_t line = number_line(h); line < 64 * set_lines_.size()) {
    set_lines_[line / 64] |= std::uint64_t{1} << (line % 64);
  }
  if (plain_[h] && std::holds_alternative<std::int64_t>(value)) {
    std::int64_t n = std::get<std::int64_t>(value);
    if (const Range r = type_range(layout_->type(h)); n < r.min || n > r.max) {
      const auto converted = convert_number(layout_->type(h), n);
      if (!converted) return converted.error();
      n = *converted;
    }
    if (n == numbers_[h]) return AbortCode::none;
    store(h, Value{n});
    return AbortCode::none;
  }
  auto v = convert_for_write(layout_->info(h), value);
  if (!v) return v.error();
  Done none;
  return commit(h, std::move(*v), Origin::internal, none);
}

AbortCode ObjectDictionary::check_download(std::uint16_t index, std::uint8_t sub,
                                           std::optional<std::size_t> size) const {
  auto h = locate(index, sub);
  if (!h) return h.error();
  const EntryInfo& info = layout_->info(*h);
  if (info.access == Access::ro || info.access == Access::const_) return AbortCode::read_only;
  if (size && !is_string(info.type)) {
    const std::size_t n = size_of(info.type);
    if (*size > n && !(info.length_tolerant && *size == 4)) return AbortCode::length_too_high;
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
  const EntryInfo& info = layout_->info(*h);
  if (origin != Origin::internal && (info.access == Access::ro || info.access == Access::const_)) {
    return AbortCode::read_only;
  }
  if (is_string(info.type)) {
    std::string s;
    s.reserve(data.size());
    for (auto b : data) s.push_back(static_cast<char>(b));
    return commit(*h, Value{std::move(s)}, origin, done);
  }
  const std::size_t n = size_of(info.type);
  const std::size_t got = data.size();
  if (length == SdoLength::segmented_unindicated && got != n) return AbortCode::type_mismatch;
  if (length == SdoLength::indicated && got > n) {
    if (!(info.length_tolerant && got == 4)) return AbortCode::length_too_high;
    const std::int64_t v = decode_le(data, DataType::integer32);
    if (v > 65535) return AbortCode::value_too_high;
    if (v < 0) return AbortCode::value_too_low;
    return commit(*h, Value{v}, origin, done);
  }
  if (got < n) return AbortCode::length_too_low;
  return commit(*h, Value{decode_le(data.first(n), info.type)}, origin, done);
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
  set_hook(write_hooks_, hooks_[h].write, std::move(hook), "write", index, sub);
  plain_.set(h, is_plain(h));
}

void ObjectDictionary::on_read(std::uint16_t index, std::uint8_t sub, ReadHook hook) {
  set_hook(read_hooks_, hooks_[handle(index, sub)].read, std::move(hook), "read", index, sub);
}

void ObjectDictionary::on_change(ChangeListener listener) {
  listeners_.push_back({{}, std::move(listener)});
  watched_.set_all();
}

void ObjectDictionary::on_change(std::initializer_list<std::pair<std::uint16_t, std::uint8_t>> entries,
                                 ChangeListener listener) {
  std::vector<bool> mine(layout_->size());
  for (const auto& [index, sub] : entries) {
    if (const auto h = find(index, sub)) {
      mine[*h] = true;
      watched_.set(*h, true);
    }
  }
  listeners_.push_back({std::move(mine), std::move(listener)});
}

std::vector<LoadIssue> ObjectDictionary::load_values(std::span<const StoredValue> values) {
  std::vector<LoadIssue> issues;
  for (const auto& sv : values) {
    auto h = locate(sv.index, sv.sub);
    if (!h) {
      issues.push_back({sv.index, sv.sub, h.error()});
      continue;
    }
    auto v = convert_for_write(layout_->info(*h), sv.value);
    if (!v) {
      issues.push_back({sv.index, sv.sub, v.error()});
      continue;
    }
    if (std::holds_alternative<std::int64_t>(*v)) {
      if (auto c = check_limits(*h, std::get<std::int64_t>(*v), true); c != AbortCode::none) {
        issues.push_back({sv.index, sv.sub, c});
        continue;
      }
    }
    const auto slot = layout_->string_slot(*h);
    if (slot == Layout::k_no_string) {
      const auto n = std::get<std::int64_t>(*v);
      if (numbers_[*h] != n) {
        ++generation_;
        ++settings_generation_;  // a bulk load counts as a change of settings, whatever it loads
      }
      numbers_[*h] = n;
    } else {
      auto& s = std::get<std::string>(*v);
      if (strings_[slot] != s) {
        ++generation_;
        ++settings_generation_;
      }
      strings_[slot] = std::move(s);
    }
  }
  return issues;
}

void ObjectDictionary::for_each(const std::function<void(const EntryInfo&, const Value&)>& fn) const {
  for (Handle h = 0; h < layout_->size(); ++h) fn(layout_->info(h), value(h));
}

}  // namespace mcemu::od
