#include "protocols/refgo/attachment.hpp"

#include <vector>

#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/command.hpp"

namespace mcemu::refgo {

Route route(AttachMode mode, bool blank, bool known) {
  switch (mode) {
    case AttachMode::none: return {true, false};
    case AttachMode::forward_all: return {true, true};
    case AttachMode::forward_unprocessed: return known || blank ? Route{true, false} : Route{false, true};
    case AttachMode::script_only: return {false, true};
  }
  return {true, false};
}

Attachment::Registration::~Registration() {
  if (auto sinks = sinks_.lock()) sinks->erase(id_);
}

Attachment::Attachment() : sinks_(std::make_shared<std::map<ConnectionId, Sink>>()) {}

std::unique_ptr<Attachment::Registration> Attachment::add_connection(Sink sink) {
  auto r = std::make_unique<Registration>();
  r->id_ = next_id_++;
  r->sinks_ = sinks_;
  (*sinks_)[r->id_] = std::move(sink);
  return r;
}

Route Attachment::route(std::string_view line) const {
  if (mode_ == AttachMode::none) return {true, false};
  const Lexed l = lex(line);
  return refgo::route(mode_, l.blank(), l.blank() || find_command(l.word()) != nullptr);
}

void Attachment::forward(ConnectionId from, std::string line) {
  if (mode_ == AttachMode::none) return;
  if (lines_.size() >= k_max_script_lines) {
    ++dropped_;
    return;
  }
  lines_.push_back({from, std::move(line)});
}

void Attachment::open(AttachMode mode) {
  mode_ = mode;
  last_read_.reset();
}

void Attachment::close() {
  mode_ = AttachMode::none;
  lines_.clear();
  last_read_.reset();
}

std::optional<std::string> Attachment::read() {
  if (lines_.empty()) return std::nullopt;
  Waiting w = std::move(lines_.front());
  lines_.pop_front();
  last_read_ = w.from;
  return std::move(w.text);
}

bool Attachment::write(std::string_view bytes) {
  if (mode_ == AttachMode::none) return false;
  if (last_read_) {
    const auto it = sinks_->find(*last_read_);
    if (it == sinks_->end()) return false;
    it->second(bytes);
    return true;
  }
  if (sinks_->empty()) return false;
  // A sink may not add or remove connections, but copy the list anyway: writing wakes adapters.
  std::vector<Sink> all;
  for (const auto& [id, sink] : *sinks_) all.push_back(sink);
  for (const auto& sink : all) sink(bytes);
  return true;
}

}  // namespace mcemu::refgo
