// The line adapter's connection (protocols/line/net/line_connection.hpp) on a fake socket, with a
// real RefGo session on a real drive: every write call the adapter makes is counted and kept
// (refgo.md §15.2 "a unit test of the net adapter with a fake socket counts exactly one write call
// per reply"), the backlog policy of §2.6 and the idle timeout are checked without a network.
#include "protocols/line/net/line_connection.hpp"

#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <deque>
#include <memory>
#include <optional>

#include "protocols/refgo/session.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::line::net {
namespace {

namespace asio = boost::asio;
using namespace std::chrono_literals;

// Both ends of the fake socket: what the test sends, what the adapter wrote (one entry per write
// call that wrote bytes: write_some or async_write_some), and switches to hold writes back (a peer
// that does not read: write_some would block, async writes wait) or to let write_some take only
// part of the bytes (a nearly full send buffer).
struct Wire {
  explicit Wire(asio::io_context& context) : io(context) {}
  asio::io_context& io;
  std::string input;                                                        // sent by the peer, not yet read
  std::function<void(const boost::system::error_code&, std::size_t)> read;  // the pending read
  asio::mutable_buffer read_buffer;
  std::vector<std::string> writes;
  bool hold_writes = false;
  std::deque<std::function<void()>> held;  // completions of held writes
  bool hold_async = false;                 // hold async writes only (write_some still works)
  std::size_t direct_limit = SIZE_MAX;     // bytes one write_some takes at most
  int direct_calls = 0;                    // write_some calls, including those that would block
  int async_calls = 0;                     // async_write_some calls
  bool eof = false;
  bool closed = false;

  void send(std::string_view bytes) {
    input.append(bytes);
    deliver();
  }
  void send_eof() {
    eof = true;
    deliver();
  }
  void deliver() {
    if (!read || (input.empty() && !eof)) return;
    auto handler = std::exchange(read, {});
    if (input.empty()) {
      asio::post(io, [handler] { handler(asio::error::eof, 0); });
      return;
    }
    const std::size_t n = asio::buffer_copy(read_buffer, asio::buffer(input));
    input.erase(0, n);
    asio::post(io, [handler, n] { handler({}, n); });
  }
  void release_writes() {
    hold_writes = false;
    hold_async = false;
    while (!held.empty()) {
      auto h = std::move(held.front());
      held.pop_front();
      h();
    }
  }
  bool reading() const { return static_cast<bool>(read); }
};

class FakeStream {
 public:
  using executor_type = asio::io_context::executor_type;
  explicit FakeStream(Wire& wire) : wire_(&wire) {}
  executor_type get_executor() { return wire_->io.get_executor(); }

  template <class MutableBuffers, class Handler>
  void async_read_some(const MutableBuffers& buffers, Handler&& handler) {
    auto h = std::make_shared<std::decay_t<Handler>>(std::forward<Handler>(handler));
    wire_->read_buffer = *asio::buffer_sequence_begin(buffers);
    wire_->read = [h](const boost::system::error_code& ec, std::size_t n) { (*h)(ec, n); };
    wire_->deliver();
  }
  void non_blocking(bool mode, boost::system::error_code&) { non_blocking_ = mode; }
  template <class ConstBuffers>
  std::size_t write_some(const ConstBuffers& buffers, boost::system::error_code& ec) {
    EXPECT_TRUE(non_blocking_) << "a direct write on a blocking socket could stall the loop";
    ++wire_->direct_calls;
    if (wire_->hold_writes || wire_->direct_limit == 0) {
      ec = asio::error::would_block;
      return 0;
    }
    std::string bytes(std::min(asio::buffer_size(buffers), wire_->direct_limit), '\0');
    asio::buffer_copy(asio::buffer(bytes), buffers);
    wire_->writes.push_back(bytes);
    ec = {};
    return bytes.size();
  }
  template <class ConstBuffers, class Handler>
  void async_write_some(const ConstBuffers& buffers, Handler&& handler) {
    ++wire_->async_calls;
    std::string bytes(asio::buffer_size(buffers), '\0');
    asio::buffer_copy(asio::buffer(bytes), buffers);
    const std::size_t n = bytes.size();
    wire_->writes.push_back(std::move(bytes));
    auto h = std::make_shared<std::decay_t<Handler>>(std::forward<Handler>(handler));
    auto complete = [this, h, n] { asio::post(wire_->io, [h, n] { (*h)(boost::system::error_code{}, n); }); };
    if (wire_->hold_writes || wire_->hold_async) {
      wire_->held.push_back(complete);
    } else {
      complete();
    }
  }
  void shutdown(asio::socket_base::shutdown_type, boost::system::error_code&) {}
  void close(boost::system::error_code&) { wire_->closed = true; }

 private:
  Wire* wire_;
  bool non_blocking_ = false;
};

struct Fixture {
  explicit Fixture(LineServerOptions options = {}) : wire(io) {
    options.name = "refgo";
    connection = std::make_shared<LineConnection<FakeStream>>(FakeStream(wire), options, PeerInfo{"fake:1", 1},
                                                              [this](LineConnectionBase*) { closed = true; });
    connection->start(std::make_unique<refgo::Session>(drive.in));
    run();
  }
  void run() {
    io.restart();
    io.poll();
  }
  // Sends bytes and runs the loop until nothing is left to do; returns the writes it caused.
  std::vector<std::string> exchange(std::string_view bytes) {
    const std::size_t before = wire.writes.size();
    wire.send(bytes);
    run();
    return {wire.writes.begin() + static_cast<std::ptrdiff_t>(before), wire.writes.end()};
  }

  asio::io_context io;
  Wire wire;
  refgo::test::Drive drive;
  // the bundle's state-file storage: its writes complete when the test says so
  mcemu::testing::MemoryStorage& storage = drive.fixture.storage();
  std::shared_ptr<LineConnection<FakeStream>> connection;
  bool closed = false;
};

// A session that wakes its adapter from inside receive(), as an SLCAN session does when the node
// answers the frame it is handing over; it checks that the bytes it was given do not change under it.
class WakingSession final : public StreamSession {
 public:
  void receive(std::string_view bytes) override {
    const std::string before(bytes);
    output_ += "<" + before + ">";
    wake();  // the adapter collects and may want to read again: not into these bytes
    if (std::string(bytes) != before) overwritten = true;
    received.push_back(before);
  }
  std::string take_output() override { return std::exchange(output_, {}); }
  void peer_closed() override {}
  bool finished() const override { return true; }

  std::vector<std::string> received;
  bool overwritten = false;

 private:
  std::string output_;
};

TEST(LineConnection, AWakeUpInsideReceiveDoesNotReadIntoTheBytesBeingParsed) {
  asio::io_context io;
  Wire wire(io);
  auto owned = std::make_unique<WakingSession>();
  WakingSession* session = owned.get();
  auto connection = std::make_shared<LineConnection<FakeStream>>(FakeStream(wire), LineServerOptions{},
                                                                 PeerInfo{"fake:1", 1}, [](LineConnectionBase*) {});
  connection->start(std::move(owned));
  wire.send("first\r");     // read at once into the adapter's buffer, handler queued
  wire.input = "second\r";  // arrives before the handler runs: a read started now would get it
  io.restart();
  io.poll();
  EXPECT_FALSE(session->overwritten);
  EXPECT_EQ(session->received, (std::vector<std::string>{"first\r", "second\r"}));
  std::string all;
  for (const auto& w : wire.writes) all += w;
  EXPECT_EQ(all, "<first\r><second\r>");
}

TEST(LineConnection, EveryReplyIsExactlyOneWriteCall) {
  Fixture f;
  const std::vector<std::string> commands = {
      "TP",  "TS",        "TPSR",  "OR6041,0,h", "OR1008,0", "OW6083,0,1000",
      "XYZ", "TI",        "SP720", "OR1234,0",   "G1000",    "A" + std::string(300, 'A'),
      "",    "OW340F,1,5"};
  for (int i = 0; i < 1000; ++i) {
    const std::string& cmd = commands[static_cast<std::size_t>(i) % commands.size()];
    const auto writes = f.exchange(cmd + "\r");
    ASSERT_EQ(writes.size(), 1U) << cmd;
    EXPECT_EQ(writes[0].back(), '>') << cmd;
    EXPECT_TRUE(writes[0] == ">" || writes[0].rfind(cmd.substr(0, 2), 0) == 0) << writes[0];
    if (i % 10 == 0) f.drive.step();
  }
  EXPECT_EQ(f.wire.writes.size(), 1000U);
  // each went out directly from the handler that read the request: no async write, no handler
  EXPECT_EQ(f.wire.direct_calls, 1000);
  EXPECT_EQ(f.wire.async_calls, 0);
}

// A send buffer that takes only part of a reply: the rest follows through async_write, in order,
// and a reply produced meanwhile waits behind it instead of being written directly before it.
TEST(LineConnection, WhatTheKernelDoesNotTakeAtOnceFollowsAsynchronouslyInOrder) {
  Fixture f;
  f.wire.direct_limit = 5;
  f.wire.hold_async = true;
  EXPECT_EQ(f.exchange("TS\rTPSR\r"), (std::vector<std::string>{"TS\r\n0", "\r\n>TPSR\r\n00000002\r\n>"}));
  EXPECT_EQ(f.wire.async_calls, 1);
  // the rest is still being written: the next reply queues behind it, nothing is written directly
  EXPECT_TRUE(f.exchange("TS\r").empty());
  EXPECT_EQ(f.wire.direct_calls, 1);
  f.wire.release_writes();
  f.run();
  std::string all;
  for (const auto& w : f.wire.writes) all += w;
  EXPECT_EQ(all, "TS\r\n0\r\n>TPSR\r\n00000002\r\n>TS\r\n0\r\n>");
  EXPECT_EQ(f.wire.direct_calls, 2);  // after the async write: direct again (5 bytes, then async)
  EXPECT_FALSE(f.closed);
}

// A peer whose send buffer is full: the direct write would block (nothing written), the reply
// goes to an async write that completes when the peer reads; the next reply is direct again.
TEST(LineConnection, AWriteThatWouldBlockWaitsForThePeer) {
  Fixture f;
  f.wire.hold_writes = true;
  EXPECT_EQ(f.exchange("TS\r"), std::vector<std::string>{"TS\r\n0\r\n>"});  // handed to async_write_some
  EXPECT_EQ(f.wire.direct_calls, 1);
  EXPECT_EQ(f.wire.async_calls, 1);
  EXPECT_EQ(f.wire.held.size(), 1U);  // not completed while the peer does not read
  f.wire.release_writes();
  f.run();
  EXPECT_EQ(f.exchange("TP\r"), std::vector<std::string>{"TP\r\n0\r\n>"});
  EXPECT_EQ(f.wire.direct_calls, 2);
  EXPECT_EQ(f.wire.async_calls, 1);
}

TEST(LineConnection, PipelinedLinesOfOneChunkLeaveInOneWrite) {
  Fixture f;
  const auto writes = f.exchange("TS\rTPSR\rOR3410,1\r");
  ASSERT_EQ(writes.size(), 1U);
  EXPECT_EQ(writes[0], "TS\r\n0\r\n>TPSR\r\n00000002\r\n>OR3410,1\r\nOR3410,1,0\r\n>");
}

TEST(LineConnection, AReplyThatWaitsForAStoreIsOneWriteWithTheLinesBehindIt) {
  Fixture f;
  EXPECT_EQ(f.exchange("OW1010,1,1702257011\rTS\r").size(), 0U);  // pending: nothing written yet
  EXPECT_FALSE(f.wire.reading());                                 // and the next lines wait (§2.5)
  f.storage.complete();
  f.run();
  ASSERT_EQ(f.wire.writes.size(), 1U);
  EXPECT_EQ(f.wire.writes[0], "OW1010,1,1702257011\r\nOW1010,1,1702257011,OK\r\n>TS\r\n0\r\n>");
  EXPECT_TRUE(f.wire.reading());
}

TEST(LineConnection, BacklogAbovePauseStopsReadingUntilBelowResume) {
  LineServerOptions o;
  o.pause_above = 4096;
  o.resume_below = 1024;
  Fixture f(o);
  f.wire.hold_writes = true;  // the peer does not read
  std::string many;
  for (int i = 0; i < 400; ++i) many += "TS\r";  // 400 × 8 reply bytes = 3200
  f.exchange(many);
  EXPECT_TRUE(f.wire.reading());  // 3200 bytes queued: below the pause mark
  f.exchange(many);
  EXPECT_FALSE(f.wire.reading());  // 6400 > 4096: paused (§2.6)
  f.wire.send(many);               // the peer keeps sending; nothing is read
  f.run();
  EXPECT_EQ(f.wire.input.size(), many.size());
  f.wire.release_writes();  // the peer reads: the backlog drains, reading resumes
  f.run();
  f.wire.release_writes();
  f.run();
  EXPECT_TRUE(f.wire.input.empty());
  std::string all;
  for (const auto& w : f.wire.writes) all += w;
  EXPECT_EQ(all.size(), 3U * 400U * 8U);  // nothing lost
  EXPECT_FALSE(f.closed);
}

TEST(LineConnection, FinAnswersTheCompleteLinesThenCloses) {
  Fixture f;
  f.wire.send("TS\rTP");
  f.wire.send_eof();
  f.run();
  ASSERT_EQ(f.wire.writes.size(), 1U);
  EXPECT_EQ(f.wire.writes[0], "TS\r\n0\r\n>");
  EXPECT_TRUE(f.closed);
  EXPECT_TRUE(f.wire.closed);
}

// Runs the loop until `pred` holds or `limit` passes; returns the time it took.
template <class Pred>
std::chrono::steady_clock::duration run_until(asio::io_context& io, Pred pred, std::chrono::milliseconds limit) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!pred() && std::chrono::steady_clock::now() - t0 < limit) {
    io.restart();
    io.run_one_for(10ms);
  }
  return std::chrono::steady_clock::now() - t0;
}

TEST(LineConnection, IdleTimeoutClosesAQuietConnectionNotBefore) {
  LineServerOptions o;
  o.idle_timeout = 100ms;
  Fixture f(o);
  f.exchange("TS\r");
  const auto t0 = std::chrono::steady_clock::now();
  run_until(
      f.io, [&] { return f.closed; }, 60s);
  EXPECT_TRUE(f.closed);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 100ms);
}

TEST(LineConnection, IdleTimeoutCountsFromTheLastByteReceived) {
  LineServerOptions o;
  o.idle_timeout = 300ms;
  Fixture f(o);
  run_until(
      f.io, [] { return false; }, 200ms);
  ASSERT_FALSE(f.closed);
  f.exchange("T");  // a byte, not even a line, restarts the count
  const auto last_byte = std::chrono::steady_clock::now();
  run_until(
      f.io, [&] { return f.closed; }, 60s);
  EXPECT_TRUE(f.closed);
  EXPECT_GE(std::chrono::steady_clock::now() - last_byte, 300ms);
}

TEST(LineConnection, PausedReadingIsNotIdleTime) {
  LineServerOptions o;
  o.idle_timeout = 50ms;
  Fixture f(o);
  f.exchange("OW1010,1,1702257011\r");  // waits for the Store: reading paused
  ASSERT_FALSE(f.wire.reading());
  run_until(
      f.io, [] { return false; }, 300ms);
  EXPECT_FALSE(f.closed);
  f.storage.complete();
  f.run();
  run_until(
      f.io, [&] { return f.closed; }, 60s);  // reading again: now it is idle time
  EXPECT_TRUE(f.closed);
}

TEST(LineConnection, NoIdleTimeoutByDefault) {
  Fixture f;
  run_until(
      f.io, [] { return false; }, 200ms);
  EXPECT_FALSE(f.closed);
}

}  // namespace
}  // namespace mcemu::line::net
