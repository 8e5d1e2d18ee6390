// A MovingCap CODE script attached to port 10001 (refgo.md §5, scripting.md §6.3–§6.6): the
// attachment mode, the dispatch rule of §5.1, the queue of lines waiting for the script (at most
// 64 over all connections, §5.4) and the connections a script reply can go to (§5.3).
//
// Contract: pure and single-threaded (event-loop thread). One per interpreter. Sessions register
// while they live (add_connection / remove_connection through a Registration, which may outlive
// the attachment); the script engine calls open/read/write/close and close() on every way out of
// a run (scripting.md §3.3).
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace mcemu::refgo {

inline constexpr std::size_t k_max_script_lines = 64;

enum class AttachMode : std::uint8_t { none = 0, forward_all = 1, forward_unprocessed = 2, script_only = 3 };

// What happens to one complete, not over-long line (§5.1).
struct Route {
  bool execute = true;   // the built-in interpreter executes it and replies
  bool forward = false;  // the line is queued for refgo.read()
};
// `known` = the line is blank or its command word is in the command table.
Route route(AttachMode mode, bool blank, bool known);

class Attachment {
 public:
  using ConnectionId = std::uint64_t;
  using Sink = std::function<void(std::string_view bytes)>;

  // A session's place in the attachment; removes itself on destruction, also after the attachment
  // has gone.
  class Registration {
   public:
    Registration() = default;
    Registration(const Registration&) = delete;
    Registration& operator=(const Registration&) = delete;
    ~Registration();
    ConnectionId id() const { return id_; }

   private:
    friend class Attachment;
    std::weak_ptr<std::map<ConnectionId, Sink>> sinks_;
    ConnectionId id_ = 0;
  };

  Attachment();
  std::unique_ptr<Registration> add_connection(Sink sink);

  // ---- session side
  // §5.1 for one line as delivered by the line assembler (control bytes removed).
  Route route(std::string_view line) const;
  // Queue a line for the script; dropped (and counted) when 64 are waiting.
  void forward(ConnectionId from, std::string line);

  // ---- script side
  void open(AttachMode mode);  // attach, or change the mode of the attachment
  void close();                // detach; unread lines are dropped
  std::optional<std::string> read();
  // To the connection of the line most recently read, or to every connection if none was read since
  // open(). False: not attached or no such connection.
  bool write(std::string_view bytes);

  AttachMode mode() const { return mode_; }
  bool attached() const { return mode_ != AttachMode::none; }
  std::size_t waiting() const { return lines_.size(); }
  std::uint64_t dropped() const { return dropped_; }
  std::size_t connections() const { return sinks_->size(); }

 private:
  struct Waiting {
    ConnectionId from;
    std::string text;
  };
  AttachMode mode_ = AttachMode::none;
  std::deque<Waiting> lines_;
  std::optional<ConnectionId> last_read_;
  std::uint64_t dropped_ = 0;
  ConnectionId next_id_ = 1;
  std::shared_ptr<std::map<ConnectionId, Sink>> sinks_;
};

}  // namespace mcemu::refgo
