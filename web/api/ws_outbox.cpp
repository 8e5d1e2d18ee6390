#include "web/api/ws_outbox.hpp"

#include <algorithm>

namespace mcemu::web::api {

void WsOutbox::push_status(Message message) {
  if (!message) return;
  if (status_queued_) {
    const auto it = std::find_if(queue_.begin(), queue_.end(), [](const Entry& e) { return e.status; });
    it->message = std::move(message);
    return;
  }
  queue_.push_back({std::move(message), true});
  status_queued_ = true;
}

bool WsOutbox::push(Message message) {
  if (!message) return true;
  if (message->size() > limit_ - std::min(limit_, bytes_)) return false;
  bytes_ += message->size();
  queue_.push_back({std::move(message), false});
  return true;
}

WsOutbox::Message WsOutbox::pop() {
  if (queue_.empty()) return nullptr;
  Entry e = std::move(queue_.front());
  queue_.pop_front();
  if (e.status) {
    status_queued_ = false;
  } else {
    bytes_ -= e.message->size();
  }
  return std::move(e.message);
}

}  // namespace mcemu::web::api
