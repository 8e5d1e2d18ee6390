// One RefGo connection (refgo.md §1.4, §2, §3): frames the byte stream into lines, executes them in
// order through the shared interpreter and queues each reply as one contiguous unit.
//
// Contract (line::StreamSession): single-threaded; never throws on input. Over-long lines are
// answered ">" without being executed (§2.4). While a line's reply is pending (a Store, §2.5) the
// following lines of this connection wait in order and paused() is true; when the reply arrives it
// is queued, the waiting lines run, and wake() tells the adapter. After peer_closed() the complete
// lines are still answered; finished() turns true when none is left. A pending reply that arrives
// after the session was destroyed is dropped. While a script is attached (refgo.md §5) each line is
// routed by the interpreter's attachment: executed, forwarded to the script, or both; the script's
// replies (refgo.write) are queued here as they come, outside the order of the built-in replies.
//
// Taps (refgo.md §13, web.md §9): the observer sees every complete line as received and every line
// handed to (or dropped by) the script queue; with a reply sink every reply unit — a built-in
// reply, the ">" of an over-long line, a script's refgo.write — goes to the sink instead of the
// output queue, so that the caller can trace, drop or delay each one.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "base/liveness.hpp"
#include "protocols/line/line_assembler.hpp"
#include "protocols/line/stream_session.hpp"
#include "protocols/refgo/attachment.hpp"

namespace mcemu::refgo {

class Interpreter;

class Session final : public line::StreamSession {
 public:
  struct Observer {
    std::function<void(const line::Line& line)> received;  // every complete line, over-long ones too
    // A line given to the script's queue (discarded = dropped because 64 lines were waiting).
    std::function<void(std::string_view text, bool discarded)> to_script;
  };
  using ReplySink = std::function<void(std::string reply)>;

  explicit Session(Interpreter& interpreter);
  ~Session() override;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void receive(std::string_view bytes) override;
  std::string take_output() override;
  void peer_closed() override;
  bool finished() const override;
  bool paused() const override { return waiting_; }

  void set_observer(Observer o) { observer_ = std::move(o); }
  void set_reply_sink(ReplySink sink) { sink_ = std::move(sink); }

 private:
  void run();
  void emit(std::string reply);
  void on_late_reply(const std::string& reply);

  Interpreter& interpreter_;
  line::LineAssembler assembler_;
  std::deque<line::Line> queue_;  // complete lines not yet executed
  std::string output_;
  Observer observer_;
  ReplySink sink_;
  bool waiting_ = false;
  bool closed_ = false;
  base::LivenessToken alive_;              // late replies check this is still alive
  std::function<void(std::string)> late_;  // the late-reply function every executed line gets (checks alive_)
  std::vector<line::Line> lines_;          // receive()'s scratch: the complete lines of one chunk
  std::unique_ptr<Attachment::Registration> registration_;
};

}  // namespace mcemu::refgo
