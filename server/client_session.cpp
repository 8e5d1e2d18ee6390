#include "server/client_session.hpp"

#include <utility>

namespace mcemu::server {

ClientSession::ClientSession(std::unique_ptr<line::StreamSession> inner, base::Liveness owner, Hooks hooks,
                             std::string what, boost::asio::any_io_executor executor)
    : inner_(std::move(inner)),
      owner_(std::move(owner)),
      hooks_(std::move(hooks)),
      what_(std::move(what)),
      timer_(std::move(executor)) {
  inner_->set_wake([this] { wake(); });
  if (alive()) {
    hooks_.sync();
    hooks_.link(true);
    if (hooks_.note) hooks_.note(what_ + " connected");
    trace(trace::Dir::event, "connect");
  }
}

ClientSession::~ClientSession() {
  if (alive()) {
    hooks_.sync();
    hooks_.link(false);
    if (hooks_.note) hooks_.note(what_ + " disconnected");
    trace(trace::Dir::event, "disconnect");
  }
}

void ClientSession::receive(std::string_view bytes) {
  if (!alive()) return inner_->receive(bytes);
  hooks_.sync();
  hooks_.activity();
  inner_->receive(bytes);
  hooks_.wake();
}

std::string ClientSession::take_output() {
  std::string out = inner_->take_output();
  release(out);
  if (!out.empty() && alive()) hooks_.activity();
  return out;
}

void ClientSession::peer_closed() {
  if (alive()) hooks_.sync();
  inner_->peer_closed();
  if (alive()) hooks_.wake();
}

void ClientSession::closing(std::string_view reason) {
  trace(trace::Dir::event, reason);
  inner_->closing(reason);
}

void ClientSession::reply(std::string text) {
  const auto v = hooks_.reply_verdict && alive() ? hooks_.reply_verdict() : device::Verdict{};
  if (v.action == device::Verdict::Action::drop) {
    trace(trace::Dir::event, device::verdict_text(v, "reply") + ": " + text);
    if (hooks_.replied && alive()) hooks_.replied(false);
    return;
  }
  if (v.action == device::Verdict::Action::delay) trace(trace::Dir::event, device::verdict_text(v, "reply"));
  if (v.action == device::Verdict::Action::send && held_.empty()) {  // the common case: no clock read
    trace(trace::Dir::tx, text);
    sent();
    ready_ += text;
    return;
  }
  const auto now = wall_now();
  if (auto at_once = held_.push(std::move(text), now, now + v.delay)) {
    trace(trace::Dir::tx, *at_once);
    sent();
    ready_ += *at_once;
  }
}

void ClientSession::sent() const {
  if (hooks_.replied && alive()) hooks_.replied(true);
}

void ClientSession::trace(trace::Dir dir, std::string_view text, trace::Flags flags) const {
  if (hooks_.trace && alive()) hooks_.trace(dir, text, flags);
}

ClientSession::Ms ClientSession::wall_now() {
  return std::chrono::duration_cast<Ms>(std::chrono::steady_clock::now().time_since_epoch());
}

void ClientSession::release(std::string& out) {
  if (held_.empty()) {
    out += std::exchange(ready_, {});
    return;
  }
  auto due_now = held_.pop_due(wall_now());
  if (!due_now.empty() && alive()) hooks_.sync();  // the trace shows the drive time of sending
  for (auto& r : due_now) {
    trace(trace::Dir::tx, r);
    sent();
    ready_ += r;
  }
  out += std::exchange(ready_, {});
  const auto due = held_.next_due();
  if (!due || (armed_ && *armed_ == *due)) return;
  armed_ = due;
  timer_.expires_at(std::chrono::steady_clock::time_point(*due));
  timer_.async_wait([self = token_.watch(), this](const boost::system::error_code& ec) {
    if (ec || !self) return;
    armed_.reset();
    wake();  // the adapter collects: take_output() releases what is due
  });
}

}  // namespace mcemu::server
