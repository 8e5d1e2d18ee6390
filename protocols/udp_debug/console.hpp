// The drive's UDP debug console without a socket (udp-debug.md §2, §3, §5): listener registration,
// the 8 KiB backlog, per-listener output queues and the packing of messages into datagrams.
//
// Contract: pure and single-threaded. The net adapter (net/udp_debug_service.hpp) feeds every
// received datagram to on_datagram() and, when has_output() turns true, posts one flush that sends
// what take_datagrams() returns. A message is a byte string that carries its own line ending.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::udp_debug {

inline constexpr std::size_t k_max_listeners = 4;
inline constexpr std::size_t k_backlog_bytes = 8192;
inline constexpr std::size_t k_max_datagram = 1024;

// A UDP address as text ("127.0.0.1") and port; compared exactly.
struct Peer {
  std::string address;
  std::uint16_t port = 0;
  auto operator<=>(const Peer&) const = default;
};

struct Datagram {
  Peer to;
  std::string payload;
};

// When a datagram arrived: drive time and UTC wall time ("2026-01-15T10:15:02.123Z"), as the
// adapter knows them (udp-debug.md §6 shows the registration time).
struct Stamp {
  std::uint64_t drive_ms = 0;
  std::string wall;
};

struct Listener {
  Peer peer;
  std::uint64_t registered_seq = 0;  // order of the latest registration (larger = newer)
  Stamp registered;                  // time of the latest registration
};

// Packs whole messages into datagrams of at most `max` bytes; a longer message is cut into
// `max`-byte pieces sent alone, its remainder packed like a message of its own (udp-debug.md §5.2).
std::vector<std::string> pack(std::span<const std::string> messages, std::size_t max = k_max_datagram);

// True for a registration payload: 1–4 bytes, each CR or LF (udp-debug.md §2.1).
bool is_registration(std::string_view payload);

class Console {
 public:
  enum class Received : std::uint8_t { registered, ignored, own };

  // The socket's own bound address: datagrams from it are ignored (udp-debug.md §1.3).
  void set_own(Peer own) { own_ = std::move(own); }

  // A datagram arrived. A registration queues the initial response of §2.3 to its sender.
  Received on_datagram(const Peer& from, std::string_view payload, Stamp stamp = {});
  // One console message: to every listener, or into the backlog while nobody listens (§3).
  void emit(std::string message);

  bool has_output() const;
  // Everything queued so far, packed per listener in registration order.
  std::vector<Datagram> take_datagrams();

  // Power cycle (persistence.md §7): listeners, backlog and unsent output are forgotten.
  void forget_all();

  const std::vector<Listener>& listeners() const { return listeners_; }
  std::size_t backlog_bytes() const { return backlog_size_; }
  std::size_t backlog_messages() const { return backlog_.size(); }
  std::uint64_t ignored() const { return ignored_; }

 private:
  struct Queue {
    Peer to;
    std::vector<std::string> messages;
  };
  void queue_to(const Peer& to, std::string message);
  void add_to_backlog(std::string message);

  Peer own_;
  std::vector<Listener> listeners_;
  std::deque<std::string> backlog_;
  std::size_t backlog_size_ = 0;
  std::vector<Queue> queues_;
  std::uint64_t next_seq_ = 1;
  std::uint64_t ignored_ = 0;
};

}  // namespace mcemu::udp_debug
