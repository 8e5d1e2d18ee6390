// One connection of the line adapter (line_server.hpp): read loop, session, write queue, backlog
// policy, half-close and the optional idle timeout. A template over the stream so that a unit test
// can drive the real adapter code with a fake socket (refgo.md §15.2: one write call per reply);
// LineServer instantiates it with tcp::socket.
//
// Stream: Asio's AsyncReadStream + AsyncWriteStream (get_executor, async_read_some,
// async_write_some) plus non_blocking(bool, ec), write_some(buffers, ec), shutdown(shutdown_type,
// ec) and close(ec), as tcp::socket has.
//
// Writes: replies are first written directly (one non-blocking write_some, in the handler that
// produced them); only what the kernel does not take at once — a peer that reads slowly — goes
// through async_write. A request-reply exchange thus costs one read and one write call and no
// write handler on the event loop (refgo.md §15.2: one write call per reply).
// Lifetime: owned through shared_ptr by the server's connection set until close(); async handlers
// hold a shared_ptr. Threading: the executor's single thread only.
#pragma once

#include <spdlog/spdlog.h>

#include <boost/asio/buffer.hpp>
#include <boost/asio/error.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/socket_base.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/connection_ids.hpp"
#include "protocols/line/stream_session.hpp"

namespace mcemu::line::net {

struct LineServerOptions {
  std::string name;  // "refgo", "slcan": used in log lines
  std::string flag;  // the command-line flag that sets the port, for the bind error message
  std::size_t max_clients = 8;
  std::string max_clients_flag = "--max-clients";
  std::size_t read_chunk = 4096;
  std::size_t pause_above = 256 * 1024;
  std::size_t resume_below = 64 * 1024;
  bool close_on_overflow = false;
  // --idle-timeout: close a connection that sent nothing for this long while mcemu was waiting to
  // read from it (time in which reading is paused, by a backlog or a pending Store, is not idle
  // time: mcemu cannot tell whether the peer sent anything). 0 = off.
  std::chrono::milliseconds idle_timeout{0};
  // The drive's connection ids, shared with its other listeners (base/connection_ids.hpp); empty =
  // this server counts from 1 on its own.
  std::shared_ptr<base::ConnectionIds> ids;
};

struct PeerInfo {
  std::string address;   // "127.0.0.1:53122"
  std::uint64_t id = 0;  // unique per accepted connection
};

class LineConnectionBase {
 public:
  virtual ~LineConnectionBase() = default;
  virtual void close() = 0;
};

template <class Stream>
class LineConnection final : public LineConnectionBase, public std::enable_shared_from_this<LineConnection<Stream>> {
 public:
  // `on_closed` runs once, from close(): the owner forgets the connection.
  LineConnection(Stream stream, const LineServerOptions& options, PeerInfo peer,
                 std::function<void(LineConnectionBase*)> on_closed)
      : stream_(std::move(stream)),
        options_(options),
        peer_(std::move(peer)),
        on_closed_(std::move(on_closed)),
        buffer_(options.read_chunk),
        idle_timer_(stream_.get_executor()) {}

  void start(std::unique_ptr<StreamSession> session) {
    session_ = std::move(session);
    boost::system::error_code ec;
    stream_.non_blocking(true, ec);  // a direct write must never block the loop
    direct_writes_ = !ec;
    std::weak_ptr<LineConnection> weak = this->shared_from_this();
    session_->set_wake([weak] {
      if (auto self = weak.lock()) self->on_session_output();
    });
    do_read();
    if (options_.idle_timeout.count() > 0) arm_idle(options_.idle_timeout);
  }

  void close() override {
    if (closed_) return;
    closed_ = true;
    boost::system::error_code ec;
    stream_.shutdown(boost::asio::socket_base::shutdown_both, ec);
    stream_.close(ec);
    idle_timer_.cancel();
    if (session_) session_->set_wake({});
    auto keep = this->shared_from_this();  // the owner may hold the last reference
    if (on_closed_) std::exchange(on_closed_, {})(this);
  }

  Stream& stream() { return stream_; }

 private:
  using clock = std::chrono::steady_clock;

  std::size_t backlog() const { return pending_.size() + in_flight_.size(); }

  bool may_read() const {
    // receiving_: the session is still working on buffer_ (its wake-up may arrive from inside
    // receive(), e.g. a CANopen response to the sender's own frame); a read now would overwrite
    // the bytes it has not parsed yet.
    if (closed_ || reading_ || receiving_ || peer_eof_ || session_->paused()) return false;
    return !read_paused_for_backlog_;
  }

  void do_read() {
    if (!may_read()) return;
    reading_ = true;
    if (options_.idle_timeout.count() > 0) idle_since_ = clock::now();
    stream_.async_read_some(boost::asio::buffer(buffer_),
                            [self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t n) {
                              self->on_read(ec, n);
                            });
  }

  void on_read(const boost::system::error_code& ec, std::size_t n) {
    reading_ = false;
    if (closed_) return;
    if (ec == boost::asio::error::eof) {
      peer_eof_ = true;
      session_->peer_closed();
      collect();
      return;
    }
    if (ec) {
      spdlog::debug("{}: {} disconnected ({})", options_.name, peer_.address, ec.message());
      close();
      return;
    }
    receiving_ = true;
    session_->receive(std::string_view(buffer_.data(), n));
    receiving_ = false;
    collect();
    // The next read starts after the handlers the loop already has ready (the other connections
    // of this epoll batch): by then a client that got its reply has often sent its next request,
    // so the read finds it at once instead of costing a recv that would block (EAGAIN) and a trip
    // through epoll (echo_ratio, 16 connections: ~1 recv per request instead of ~2, +1.5 points).
    boost::asio::post(stream_.get_executor(), [self = this->shared_from_this()] { self->do_read(); });
  }

  void on_session_output() {
    if (closed_) return;
    collect();
    do_read();
  }

  // Moves the session's output into the write queue, applies the backlog policy, starts a write
  // and closes a finished session once everything is written.
  void collect() {
    if (closed_) return;
    pending_ += session_->take_output();
    if (backlog() > options_.pause_above) {
      if (options_.close_on_overflow) {
        spdlog::warn("{}: closing {}: output queue above {} bytes (client does not read)", options_.name, peer_.address,
                     options_.pause_above);
        session_->closing("queue overflow");
        close();
        return;
      }
      read_paused_for_backlog_ = true;
    }
    do_write();
    maybe_finish();
  }

  void do_write() {
    if (writing_ || pending_.empty() || closed_) return;
    if (direct_writes_ && !write_directly()) return;
    writing_ = true;
    in_flight_.swap(pending_);
    boost::asio::async_write(
        stream_, boost::asio::buffer(in_flight_),
        [self = this->shared_from_this()](const boost::system::error_code& ec, std::size_t) { self->on_write(ec); });
  }

  // One non-blocking write of everything pending. Returns true if bytes are left for async_write
  // (the kernel's send buffer is full); false when all went out or the connection was closed.
  bool write_directly() {
    boost::system::error_code ec;
    const std::size_t n = stream_.write_some(boost::asio::buffer(pending_), ec);
    if (ec && ec != boost::asio::error::would_block && ec != boost::asio::error::try_again) {
      spdlog::debug("{}: {} disconnected while writing ({})", options_.name, peer_.address, ec.message());
      close();
      return false;
    }
    if (n < pending_.size()) {
      pending_.erase(0, n);
      return true;
    }
    pending_.clear();
    if (read_paused_for_backlog_ && backlog() < options_.resume_below) read_paused_for_backlog_ = false;
    return false;
  }

  void on_write(const boost::system::error_code& ec) {
    writing_ = false;
    in_flight_.clear();
    if (closed_) return;
    if (ec) {
      spdlog::debug("{}: {} disconnected while writing ({})", options_.name, peer_.address, ec.message());
      close();
      return;
    }
    if (read_paused_for_backlog_ && backlog() < options_.resume_below) read_paused_for_backlog_ = false;
    do_write();
    maybe_finish();
    do_read();
  }

  void maybe_finish() {
    if (closed_ || !peer_eof_ || !session_->finished() || writing_ || !pending_.empty()) return;
    boost::system::error_code ec;
    stream_.shutdown(boost::asio::socket_base::shutdown_send, ec);
    close();
  }

  // The idle check runs once per timeout period at most, not per read: a read only notes the time.
  void arm_idle(clock::duration after) {
    idle_timer_.expires_after(after);
    idle_timer_.async_wait([self = this->shared_from_this()](const boost::system::error_code& ec) {
      if (!ec) self->on_idle_timer();
    });
  }

  void on_idle_timer() {
    if (closed_) return;
    if (!reading_) {  // paused or between a read and the next: not idle time
      arm_idle(options_.idle_timeout);
      return;
    }
    const auto idle = clock::now() - idle_since_;
    if (idle >= options_.idle_timeout) {
      spdlog::info("{}: closing {}: nothing received for {} s (--idle-timeout)", options_.name, peer_.address,
                   std::chrono::duration_cast<std::chrono::duration<double>>(options_.idle_timeout).count());
      session_->closing("idle timeout");
      close();
      return;
    }
    arm_idle(options_.idle_timeout - idle);
  }

  Stream stream_;
  const LineServerOptions options_;  // a copy: handlers may run after the server is gone
  PeerInfo peer_;
  std::function<void(LineConnectionBase*)> on_closed_;
  std::unique_ptr<StreamSession> session_;
  std::vector<char> buffer_;
  std::string pending_;
  std::string in_flight_;
  boost::asio::steady_timer idle_timer_;
  clock::time_point idle_since_{};
  bool reading_ = false;
  bool writing_ = false;
  bool peer_eof_ = false;
  bool closed_ = false;
  bool read_paused_for_backlog_ = false;
  bool direct_writes_ = false;  // the stream is in non-blocking mode
  bool receiving_ = false;      // inside session_->receive(): buffer_ is in use
};

}  // namespace mcemu::line::net
