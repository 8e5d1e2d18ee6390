// The object dictionary: the one store of drive state (object-dictionary.md §3.3).
//
// Contract:
// - Single-threaded: every call happens on the event-loop thread. Hooks may write other entries
//   (re-entrant writes are allowed); entries never move after construction, so Handles and
//   EntryInfo pointers stay valid for the dictionary's lifetime (the entries live in the shared
//   Layout, drive/od/layout.hpp; the dictionary holds the values and hooks).
// - Every write runs the checks of object-dictionary.md §4.1 in order; the first failure is the
//   result and a refused write changes nothing. A write hook runs after the checks and may refuse
//   (its code is the result), replace the value to be stored, or answer `pending` after taking
//   the completion callback (Store/Restore only).
// - Change listeners are called after every change of a stored value, whatever the origin, but not
//   by load_values() (bulk load: no hooks, no notifications).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "drive/od/abort_code.hpp"
#include "drive/od/layout.hpp"
#include "drive/od/types.hpp"

namespace mcemu::model {
struct ModelPreset;
}

namespace mcemu::od {

// Completion of a write that answered `pending` (called later on the event-loop thread).
using Done = std::function<void(AbortCode)>;

// The request a write hook sees. `value` is what will be stored if the hook returns none; the hook
// may replace it. To answer later, return AbortCode::pending after moving `*done` (may be empty).
struct WriteRequest {
  const EntryInfo& info;
  Origin origin;
  const Value& stored;
  Value value;
  Done* done;
};
using WriteHook = std::function<AbortCode(WriteRequest&)>;
// Produces the value of an entry on read (strings, mirrors). A failure reads as 0x08000000.
using ReadHook = std::function<Result<Value>(const EntryInfo&)>;
using ChangeListener = std::function<void(const EntryInfo&, const Value&)>;

// One write as the write tap sees it (the master lint, docs/lint.md §2): what was asked and the
// result, after write() or write_bytes() returned (its hook and any writes the hook made included).
struct WriteNote {
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::int64_t value = 0;  // the number as converted for the entry (write_bytes: decoded); 0 for strings
  Origin origin = Origin::internal;
  AbortCode result = AbortCode::none;
  bool helper = false;  // made inside a helper sequence (HelperScope, drive-core.md §12)
};
using WriteTap = std::function<void(const WriteNote&)>;

// How an SDO download states its length (object-dictionary.md §3.1).
enum class SdoLength : std::uint8_t { indicated, expedited_unindicated, segmented_unindicated };

struct StoredValue {
  std::uint16_t index;
  std::uint8_t sub;
  Value value;
};
struct LoadIssue {
  std::uint16_t index;
  std::uint8_t sub;
  AbortCode code;
};

class ObjectDictionary {
 public:
  // The dictionary of a preset: its XDD base, the additions of §8.3 and the factory values of §7
  // and models.md (drive/od/model_tables.cpp), in the preset's shared layout (preset_layout()).
  explicit ObjectDictionary(const model::ModelPreset& preset);
  // A dictionary of the given entries (tests; sorted and validated here), in a layout of its own.
  explicit ObjectDictionary(std::vector<EntryInfo> entries);
  // A dictionary of a layout (shared with other dictionaries), every value at its factory value.
  explicit ObjectDictionary(std::shared_ptr<const Layout> layout);

  ObjectDictionary(const ObjectDictionary&) = delete;
  ObjectDictionary& operator=(const ObjectDictionary&) = delete;

  Result<Value> read(std::uint16_t index, std::uint8_t sub) const;
  Result<std::int64_t> read_number(std::uint16_t index, std::uint8_t sub) const;
  // SDO upload bytes: N little-endian bytes for numbers, the characters for strings.
  Result<std::vector<std::byte>> read_bytes(std::uint16_t index, std::uint8_t sub) const;

  AbortCode write(std::uint16_t index, std::uint8_t sub, const Value& value, Origin origin, Done done = {});
  AbortCode write_bytes(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data, SdoLength length,
                        Origin origin = Origin::sdo, Done done = {});
  // Checks 1–4 of §4.1 alone, for an SDO download initiate (size = indicated size, if any).
  AbortCode check_download(std::uint16_t index, std::uint8_t sub, std::optional<std::size_t> size) const;
  // Checks 1–3 of a read alone, for an SDO upload initiate.
  AbortCode check_upload(std::uint16_t index, std::uint8_t sub) const;

  // At most one hook of each kind per entry, registered by its owner: a second registration
  // throws std::logic_error (an empty hook removes the one there).
  void on_write(std::uint16_t index, std::uint8_t sub, WriteHook hook);
  void on_read(std::uint16_t index, std::uint8_t sub, ReadHook hook);
  // Called after a stored value changed (not by load_values()). The second form watches only the
  // entries named (those the dictionary lacks are skipped): a change of any other entry does not
  // call it, so the actual values a moving drive writes every step cost it nothing (issue 26).
  void on_change(ChangeListener listener);
  void on_change(std::initializer_list<std::pair<std::uint16_t, std::uint8_t>> entries, ChangeListener listener);
  // The one write tap (empty = none, the default): called after every write() and write_bytes() —
  // not set() and not load_values(). Without a tap a write costs one branch more.
  void set_write_tap(WriteTap tap) { tap_ = std::move(tap); }

  // While one lives, the writes are marked `helper` for the tap: a helper sequence (drive-core.md
  // §12) is the drive's own procedure, not a master's decision.
  class HelperScope {
   public:
    explicit HelperScope(ObjectDictionary& od) : od_(od) { ++od_.helper_depth_; }
    ~HelperScope() { --od_.helper_depth_; }
    HelperScope(const HelperScope&) = delete;
    HelperScope& operator=(const HelperScope&) = delete;

   private:
    ObjectDictionary& od_;
  };

  // Bulk load: type and §5 limits checked per value (a bad one keeps its old value and is
  // reported); no access check, no hooks, no change notifications.
  std::vector<LoadIssue> load_values(std::span<const StoredValue> values);

  const EntryInfo* info(std::uint16_t index, std::uint8_t sub) const;
  bool has_object(std::uint16_t index) const;
  // Ascending (index, sub); the value is the stored value (read hooks are not run).
  void for_each(const std::function<void(const EntryInfo&, const Value&)>& fn) const;
  std::size_t size() const { return layout_->size(); }
  const std::shared_ptr<const Layout>& layout() const { return layout_; }
  // Counts every change of a stored value, also by load_values(): equal counts mean no value
  // changed in between (the quiet-step checks of the clock, drive-core.md §2).
  std::uint64_t generation() const { return generation_; }
  // The same for the entries a master can write (Layout::setting): a moving drive changes its
  // actual values every step, its settings rarely, so a cache of what settings imply (the core's
  // enable masks) stays valid while this count does.
  std::uint64_t settings_generation() const { return settings_generation_; }

  // Fast paths for components that own entries (the drive core). find() resolves once;
  // number() reads the stored value (no hook); set() is an internal write with the full checks.
  std::optional<Handle> find(std::uint16_t index, std::uint8_t sub) const;
  Handle handle(std::uint16_t index, std::uint8_t sub) const;  // throws std::out_of_range if absent
  const EntryInfo& info(Handle h) const { return layout_->info(h); }
  std::int64_t number(Handle h) const { return numbers_[h]; }
  // Starts loading into the caches the stored numbers the drive itself wrote in its last steps
  // (set(): the actual values a moving drive writes every step) and the flags set() tests. A hint
  // for a fleet's clock before it steps this drive (sim::Steppable::prefetch); changes nothing.
  void prefetch() const;
  Value value(Handle h) const;
  // read() of a resolved entry: the access check and the read hook, no lookup.
  Result<Value> read(Handle h) const;
  AbortCode set(Handle h, const Value& v);

  // Reads of entries that must exist for the caller's model (throws std::out_of_range otherwise).
  std::int64_t number(std::uint16_t index, std::uint8_t sub) const { return number(handle(index, sub)); }

 private:
  // 1-based positions of an entry's hooks in write_hooks_/read_hooks_, 0 = none.
  struct HookSlots {
    std::uint16_t write = 0;
    std::uint16_t read = 0;
  };

  void install_error_history_rule();
  AbortCode write_value(std::uint16_t index, std::uint8_t sub, const Value& value, Origin origin, Done& done);
  AbortCode write_data(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data, SdoLength length,
                       Origin origin, Done& done);
  // The number a tap sees for a write_bytes() of `data` (0 when there is none).
  std::int64_t number_in(std::uint16_t index, std::uint8_t sub, std::span<const std::byte> data) const;
  Result<Handle> locate(std::uint16_t index, std::uint8_t sub) const { return layout_->locate(index, sub); }
  Result<Value> read_entry(Handle h) const;
  // Checks 5–6 and the hook, then stores. `v` is already of the entry's kind.
  AbortCode commit(Handle h, Value v, Origin origin, Done& done);
  AbortCode check_limits(Handle h, std::int64_t v, bool bulk) const;
  void store(Handle h, Value v);
  bool hooked_write(Handle h) const { return hooks_[h].write != 0 && write_hooks_[hooks_[h].write - 1u]; }
  // A number without limits, validator or write hook: set() needs the compact arrays only.
  bool is_plain(Handle h) const { return layout_->unchecked(h) && !hooked_write(h); }

  // The shared, immutable description (entries, key hash, types); a dictionary owns only what a
  // drive changes (issue 26): the stored numbers by handle (numbers_[h], 0 for strings: a step reads
  // 8 bytes, not a ~200-byte entry), the strings by string slot, and the hooks.
  std::shared_ptr<const Layout> layout_;
  std::vector<std::int64_t> numbers_;
  std::vector<std::string> strings_;
  std::vector<HookSlots> hooks_;
  // is_plain() by handle, as bits (a step's writes test ~100 of them: two cache lines, not ~100;
  // prefetch() can name their address).
  HandleBits plain_;  // is_plain()
  // Deques: a hook may register another while it runs.
  std::deque<WriteHook> write_hooks_;
  std::deque<ReadHook> read_hooks_;
  struct Listener {
    std::vector<bool> entries;  // by handle; empty: every entry
    ChangeListener fn;
  };
  std::vector<Listener> listeners_;
  HandleBits watched_;  // a listener wants the entry
  // The 64-byte lines of numbers_ that set() has written (bit k of word w: line 64·w + k), for
  // prefetch(); handles past the 256th line are not tracked.
  std::array<std::uint64_t, 4> set_lines_{};
  std::size_t number_line(Handle h) const;
  WriteTap tap_;
  int helper_depth_ = 0;
  std::uint64_t generation_ = 0;
  std::uint64_t settings_generation_ = 0;
};

// Value-interface conversion of §3.2 steps 1–4: checks kind and data-type range; a negative value
// for UNSIGNED32 becomes its two's-complement pattern. Returns the normalised value or the code.
Result<Value> convert_for_write(const EntryInfo& info, const Value& v);

}  // namespace mcemu::od
