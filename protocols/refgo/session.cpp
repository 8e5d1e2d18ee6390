#include "protocols/refgo/session.hpp"

#include <utility>
#include <vector>

#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo {

Session::Session(Interpreter& interpreter)
    : interpreter_(interpreter),
      assembler_(k_max_line, filter_byte),
      late_([this, alive = alive_.watch()](const std::string& late) {
        if (alive) on_late_reply(late);
      }),
      registration_(interpreter.attachment().add_connection([this](std::string_view bytes) {
        emit(std::string(bytes));
        wake();
      })) {}

Session::~Session() { alive_.end(); }

void Session::receive(std::string_view bytes) {
  if (closed_) return;
  lines_.clear();
  assembler_.feed(bytes, lines_);
  for (auto& l : lines_) {
    if (observer_.received) observer_.received(l);
    queue_.push_back(std::move(l));
  }
  run();
}

void Session::emit(std::string reply) {
  if (sink_) {
    sink_(std::move(reply));
  } else {
    output_ += reply;
  }
}

void Session::run() {
  while (!waiting_ && !queue_.empty()) {
    const line::Line l = std::move(queue_.front());
    queue_.pop_front();
    if (l.overlong) {
      emit(std::string(k_prompt));
      continue;
    }
    const Route route = interpreter_.attachment().route(l.text);
    if (route.execute) {
      auto r = interpreter_.execute(l.text, late_);
      if (r) {
        emit(std::move(*r));
      } else {
        waiting_ = true;
      }
    }
    if (route.forward) {
      auto& attachment = interpreter_.attachment();
      const auto dropped_before = attachment.dropped();
      attachment.forward(registration_->id(), l.text);
      if (observer_.to_script) observer_.to_script(l.text, attachment.dropped() != dropped_before);
    }
  }
}

void Session::on_late_reply(const std::string& reply) {
  emit(reply);
  waiting_ = false;
  run();
  wake();
}

std::string Session::take_output() { return std::exchange(output_, {}); }

void Session::peer_closed() {
  closed_ = true;
  assembler_.reset();
}

bool Session::finished() const { return closed_ && !waiting_ && queue_.empty(); }

}  // namespace mcemu::refgo
