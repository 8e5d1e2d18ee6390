// Connection ids of one drive (web.md §8.6: the `conn` of a trace event). Every listener of a drive
// (RefGo, SLCAN, HTTP) takes its ids from the one counter the drive shares with them, so no two
// connections of a drive — on whichever channel — ever show the same id. A listener without a
// shared counter counts on its own.
// PURE, header-only, single-threaded (the event loop).
#pragma once

#include <cstdint>
#include <memory>

namespace mcemu::base {

class ConnectionIds {
 public:
  std::uint64_t next() { return next_++; }  // 1, 2, 3, …

 private:
  std::uint64_t next_ = 1;
};

// What a listener holds: shared with the drive's other listeners, or its own when none is given.
inline std::shared_ptr<ConnectionIds> own_ids_unless(std::shared_ptr<ConnectionIds> shared) {
  return shared ? std::move(shared) : std::make_shared<ConnectionIds>();
}

}  // namespace mcemu::base
