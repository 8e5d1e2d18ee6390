#include "web/net/ws_hub.hpp"

#include <algorithm>

namespace mcemu::web::net {

namespace asio = boost::asio;
using clock = std::chrono::steady_clock;

WsHub::WsHub(asio::io_context& io, WsOptions options) : timer_(io), options_(options) {}

WsHub::~WsHub() { stop(); }

void WsHub::stop() {
  stopped_ = true;
  timer_.cancel();
  timer_running_ = false;
}

std::size_t WsHub::subscriber_count(api::Topic topic) const { return subscribers_[static_cast<std::size_t>(topic)]; }

std::string WsHub::hello_message() const { return api::hello_message(sources_.info ? sources_.info() : std::string{}); }

void WsHub::attach(WsClient& client) {
  if (std::find(clients_.begin(), clients_.end(), &client) == clients_.end()) clients_.push_back(&client);
  subscription_changed();
}

void WsHub::detach(WsClient& client) {
  clients_.erase(std::remove(clients_.begin(), clients_.end(), &client), clients_.end());
  recount();
}

void WsHub::subscription_changed() {
  recount();
  if (needs_period() && !timer_running_ && !stopped_) {
    next_tick_ = clock::now() + options_.period;
    arm();
  }
}

void WsHub::recount() {
  subscribers_.fill(0);
  for (const WsClient* c : clients_) {
    for (std::size_t t = 0; t < api::k_topic_count; ++t) {
      if (c->subscription().has(static_cast<api::Topic>(t))) ++subscribers_[t];
    }
  }
  if (subscriber_count(api::Topic::trace) == 0) pending_trace_.clear();
}

bool WsHub::needs_period() const {
  return subscriber_count(api::Topic::status) + subscriber_count(api::Topic::scope) +
             subscriber_count(api::Topic::trace) >
         0;
}

void WsHub::arm() {
  timer_running_ = true;
  timer_.expires_at(next_tick_);
  timer_.async_wait([this, alive = alive_.watch()](const boost::system::error_code& ec) {
    if (!alive || ec || stopped_) return;
    timer_running_ = false;
    tick();
    if (!needs_period()) return;
    // Fixed rate without bursts: a late period is not caught up.
    next_tick_ += options_.period;
    if (const auto now = clock::now(); next_tick_ <= now) next_tick_ = now + options_.period;
    arm();
  });
}

void WsHub::on_trace(const trace::Event& event) {
  if (subscriber_count(api::Topic::trace) == 0) return;
  if (pending_trace_.size() >= options_.max_trace_batch) {
    ++trace_dropped_;
    return;
  }
  pending_trace_.push_back(event);
}

void WsHub::publish_udp(std::string_view text) {
  if (subscriber_count(api::Topic::udp) == 0) return;
  const auto message = std::make_shared<const std::string>(api::udp_message(text));
  const auto clients = clients_;  // a send may detach nothing synchronously, but do not rely on it
  for (WsClient* c : clients) {
    if (c->subscription().has(api::Topic::udp)) c->send(message);
  }
}

void WsHub::tick() {
  const auto clients = clients_;
  const auto share = [](std::string text) -> api::WsOutbox::Message {
    if (text.empty()) return nullptr;
    return std::make_shared<const std::string>(std::move(text));
  };
  if (subscriber_count(api::Topic::status) > 0 && sources_.status) {
    if (const auto m = share(sources_.status())) {
      for (WsClient* c : clients) {
        if (c->subscription().has(api::Topic::status)) c->send_status(m);
      }
    }
  }
  if (subscriber_count(api::Topic::scope) > 0 && sources_.scope) {
    if (const auto m = share(sources_.scope())) {
      for (WsClient* c : clients) {
        if (c->subscription().has(api::Topic::scope)) c->send(m);
      }
    }
  }
  if (pending_trace_.empty()) return;
  const auto events = std::move(pending_trace_);
  pending_trace_.clear();
  if (!sources_.trace_message) return;
  // One message per distinct filter; most clients share one.
  std::vector<std::pair<trace::ChannelSet, api::WsOutbox::Message>> built;
  for (WsClient* c : clients) {
    if (!c->subscription().has(api::Topic::trace)) continue;
    const trace::ChannelSet filter = c->subscription().channels;
    auto it = std::find_if(built.begin(), built.end(), [&](const auto& b) { return b.first == filter; });
    if (it == built.end()) {
      api::WsOutbox::Message m;
      if (filter == trace::ChannelSet{}) {
        m = share(sources_.trace_message(events, filter));
      } else {
        std::vector<trace::Event> matching;
        for (const auto& e : events) {
          if (filter.contains(e.channel)) matching.push_back(e);
        }
        if (!matching.empty()) m = share(sources_.trace_message(matching, filter));
      }
      it = built.emplace(built.end(), filter, std::move(m));
    }
    if (it->second) c->send(it->second);
  }
}

}  // namespace mcemu::web::net
