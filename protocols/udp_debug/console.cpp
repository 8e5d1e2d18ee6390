#include "protocols/udp_debug/console.hpp"

#include <algorithm>
#include <utility>

namespace mcemu::udp_debug {

std::vector<std::string> pack(std::span<const std::string> messages, std::size_t max) {
  std::vector<std::string> out;
  std::string current;
  const auto flush = [&] {
    if (!current.empty()) out.push_back(std::exchange(current, {}));
  };
  for (const auto& m : messages) {
    std::string_view rest(m);
    if (rest.size() > max) {
      flush();
      while (rest.size() >= max) {
        out.emplace_back(rest.substr(0, max));
        rest.remove_prefix(max);
      }
    }
    if (rest.empty()) continue;
    if (current.size() + rest.size() > max) flush();
    current.append(rest);
  }
  flush();
  return out;
}

bool is_registration(std::string_view payload) {
  if (payload.empty() || payload.size() > 4) return false;
  return std::all_of(payload.begin(), payload.end(), [](char c) { return c == '\r' || c == '\n'; });
}

Console::Received Console::on_datagram(const Peer& from, std::string_view payload, Stamp stamp) {
  if (from == own_) return Received::own;
  if (!is_registration(payload)) {
    ++ignored_;
    return Received::ignored;
  }
  auto it = std::find_if(listeners_.begin(), listeners_.end(), [&](const Listener& l) { return l.peer == from; });
  if (it != listeners_.end()) {
    it->registered_seq = next_seq_++;
    it->registered = std::move(stamp);
  } else {
    if (listeners_.size() >= k_max_listeners) {
      // Evict the listener whose latest registration is the oldest (udp-debug.md §2.4).
      auto oldest = std::min_element(listeners_.begin(), listeners_.end(), [](const Listener& a, const Listener& b) {
        return a.registered_seq < b.registered_seq;
      });
      const Peer gone = oldest->peer;
      listeners_.erase(oldest);
      std::erase_if(queues_, [&](const Queue& q) { return q.to == gone; });
    }
    listeners_.push_back({from, next_seq_++, std::move(stamp)});
  }
  // Initial response (§2.3): backlog, the registration bytes, the prompt.
  while (!backlog_.empty()) {
    queue_to(from, std::move(backlog_.front()));
    backlog_.pop_front();
  }
  backlog_size_ = 0;
  queue_to(from, std::string(payload));
  queue_to(from, ">\r\n");
  return Received::registered;
}

void Console::emit(std::string message) {
  if (message.empty()) return;
  if (listeners_.empty()) {
    add_to_backlog(std::move(message));
    return;
  }
  for (const auto& l : listeners_) queue_to(l.peer, message);
}

void Console::add_to_backlog(std::string message) {
  if (message.size() >= k_backlog_bytes) {
    backlog_.clear();
    message.erase(0, message.size() - k_backlog_bytes);
    backlog_size_ = message.size();
    backlog_.push_back(std::move(message));
    return;
  }
  while (backlog_size_ + message.size() > k_backlog_bytes) {
    backlog_size_ -= backlog_.front().size();
    backlog_.pop_front();
  }
  backlog_size_ += message.size();
  backlog_.push_back(std::move(message));
}

void Console::queue_to(const Peer& to, std::string message) {
  auto it = std::find_if(queues_.begin(), queues_.end(), [&](const Queue& q) { return q.to == to; });
  if (it == queues_.end()) {
    queues_.push_back({to, {}});
    it = std::prev(queues_.end());
  }
  it->messages.push_back(std::move(message));
}

bool Console::has_output() const { return !queues_.empty(); }

std::vector<Datagram> Console::take_datagrams() {
  std::vector<Datagram> out;
  for (auto& q : queues_) {
    for (auto& payload : pack(q.messages)) out.push_back({q.to, std::move(payload)});
  }
  queues_.clear();
  return out;
}

void Console::forget_all() {
  listeners_.clear();
  backlog_.clear();
  backlog_size_ = 0;
  queues_.clear();
}

}  // namespace mcemu::udp_debug
