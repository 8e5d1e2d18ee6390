// The outbound queue of one WebSocket client (web.md §10.4), as a policy without a socket. PURE.
//
// - push_status(): the newest `status` message replaces an unsent older one in place (a slow client
//   gets fewer, fresher snapshots; status never counts against the limit);
// - push(): every other message (hello, scope, trace, udp) is queued in order while the unsent bytes
//   of these messages stay ≤ limit; a message that would exceed it is refused (push returns false) and
//   the caller closes the connection with 1008.
// Messages are shared, immutable strings: one snapshot is built per period and queued for every
// client (§10.5). pop() hands out the messages in the order they were first queued.
#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <string>

namespace mcemu::web::api {

class WsOutbox {
 public:
  using Message = std::shared_ptr<const std::string>;
  static constexpr std::size_t k_default_limit = 1024 * 1024;

  explicit WsOutbox(std::size_t limit_bytes = k_default_limit) : limit_(limit_bytes) {}

  void push_status(Message message);
  [[nodiscard]] bool push(Message message);
  // The next message to send, or null when nothing is queued.
  Message pop();

  bool empty() const { return queue_.empty(); }
  std::size_t size() const { return queue_.size(); }
  std::size_t queued_bytes() const { return bytes_; }  // unsent bytes of non-status messages
  std::size_t limit() const { return limit_; }

 private:
  struct Entry {
    Message message;
    bool status = false;
  };
  std::size_t limit_;
  std::deque<Entry> queue_;
  std::size_t bytes_ = 0;
  bool status_queued_ = false;
};

}  // namespace mcemu::web::api
