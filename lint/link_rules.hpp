// The RefGo and FAULHABER protocol rules (docs/lint.md §4.4): a request before the previous
// reply, requests faster than the real drive answers, a FAULHABER request that races the statusword
// notification of its own controlword write. State: one small slot per connection (at most
// k_slots; the least recently used is reused), with no per-step work.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "lint/reporter.hpp"

namespace mcemu::lint {

std::string_view to_string(Link l);  // "refgo", "faulhaber"

class LinkRules {
 public:
  static constexpr std::size_t k_slots = 16;
  // An unanswered request older than this is forgotten (a reply the producer never reported).
  static constexpr Ms k_forget_ms = 10000;

  void configure(const Config& c) { config_ = &c; }
  void on_request(const ProtocolRequest& r, const At& at, Reporter& rep);
  void on_reply(const ProtocolReply& r, const At& at, Reporter& rep);
  void on_closed(Conn conn);
  // A controlword write of `conn` (0: the connection whose FAULHABER request is being answered)
  // changed the statusword.
  void on_statusword_change_by(Conn conn);
  void power_on();

 private:
  struct Slot {
    bool used = false;
    Conn conn = 0;
    Link link = Link::refgo;
    std::uint64_t lru = 0;
    bool has_request = false;
    Ms last_request = 0;  // mono
    std::uint32_t unanswered = 0;
    Ms unanswered_since = 0;        // mono of the oldest unanswered request
    std::uint64_t reply_chunk = 0;  // chunk of the last request that expects a reply
    // FAULHABER: the statusword notification of this connection's controlword write
    bool cw_waiting = false;  // changed, notification not sent yet
    std::uint64_t cw_chunk = 0;
    bool cw_notified = false;   // sent; requests of cw_chunk came before it
    std::optional<At> suspect;  // a request sent while cw_waiting
  };

  Slot* find(Conn conn);
  Slot& slot(Conn conn, Link link);

  const Config* config_ = nullptr;
  std::array<Slot, k_slots> slots_{};
  std::uint64_t tick_ = 0;
  Conn answering_ = 0;  // connection of the FAULHABER request being answered
};

}  // namespace mcemu::lint
