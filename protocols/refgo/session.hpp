// One RefGo connection (refgo.md §1.4, §2, §3): frames the byte stream into lines, executes them in
// order through the shared interpreter and queues each reply as one contiguous unit.
//
// Contract (line::StreamSession): single-threaded; never throws on input. Over-long lines are
// answered ">" without being executed (§2.4). While a line's reply is pending (a Store, §2.5) the
// following lines of this connection wait in order and paused() is true; when the reply arrives it
// is queued, the waiting lines run, and wake() tells the adapter. After peer_closed() the complete
// lines are still answered; finished() turns true when none is left. A pending reply that arrives
// after the session was destroyed is dropped.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <string_view>

#include "protocols/line/line_assembler.hpp"
#include "protocols/line/stream_session.hpp"

namespace mcemu::refgo {

class Interpreter;

class Session final : public line::StreamSession {
 public:
  explicit Session(Interpreter& interpreter);
  ~Session() override;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void receive(std::string_view bytes) override;
  std::string take_output() override;
  void peer_closed() override;
  bool finished() const override;
  bool paused() const override { return waiting_; }

 private:
  void run();
  void on_late_reply(const std::string& reply);

  Interpreter& interpreter_;
  line::LineAssembler assembler_;
  std::deque<line::Line> queue_;  // complete lines not yet executed
  std::string output_;
  bool waiting_ = false;
  bool closed_ = false;
  std::shared_ptr<Session*> self_;  // late replies check this is still alive
};

}  // namespace mcemu::refgo
