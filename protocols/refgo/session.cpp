#include "protocols/refgo/session.hpp"

#include <utility>
#include <vector>

#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo {

Session::Session(Interpreter& interpreter)
    : interpreter_(interpreter), assembler_(k_max_line, filter_byte), self_(std::make_shared<Session*>(this)) {}

Session::~Session() { *self_ = nullptr; }

void Session::receive(std::string_view bytes) {
  if (closed_) return;
  std::vector<line::Line> lines;
  assembler_.feed(bytes, lines);
  for (auto& l : lines) queue_.push_back(std::move(l));
  run();
}

void Session::run() {
  while (!waiting_ && !queue_.empty()) {
    const line::Line l = std::move(queue_.front());
    queue_.pop_front();
    if (l.overlong) {
      output_ += k_prompt;
      continue;
    }
    std::weak_ptr<Session*> weak = self_;
    auto r = interpreter_.execute(l.text, [weak](const std::string& late) {
      if (auto alive = weak.lock(); alive && *alive) (*alive)->on_late_reply(late);
    });
    if (r) {
      output_ += *r;
    } else {
      waiting_ = true;
    }
  }
}

void Session::on_late_reply(const std::string& reply) {
  output_ += reply;
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
