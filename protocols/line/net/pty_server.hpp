// A pseudo-terminal that serial tools open like a COM port (faulhaber.md §2.2): the master side is
// read and written like one more connection of the line adapter (LineConnection over the master),
// the subordinate side is symlinked at a path the user chose (`--faulhaber-pty /tmp/ttyFH`).
//
// A pty has no connect: while no program has the subordinate open, the master reports POLLHUP and
// a read fails with EIO. The server polls the master every `poll` (wall time) while nobody is
// there; when a program opens the subordinate, a connection starts with a new session from the
// factory; when it closes it (EIO), the connection and its session end and the server waits for
// the next one. Nothing is written while nobody is there, so a program that opens the port later
// reads no stale bytes. Line settings a program sets (baud rate, parity) change nothing: the
// master is switched to raw mode once, at creation.
//
// The symlink is created at start (an existing symlink there is replaced; any other file is an
// error) and removed when the server is destroyed, if it still points at this pty. Linux/POSIX.
// Threading: the io_context's single thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>
#include <string>

#include "protocols/line/net/line_connection.hpp"
#include "protocols/line/net/line_server.hpp"

namespace mcemu::line::net {

struct PtyOptions {
  std::string link_path;   // where the subordinate side is symlinked
  std::string flag;        // "--faulhaber-pty", for error messages
  LineServerOptions line;  // name, output limits, close_on_overflow (max_clients and idle_timeout unused)
  std::chrono::milliseconds poll{50};
};

class PtyServer {
 public:
  // Opens the pseudo-terminal and creates the symlink; throws std::runtime_error with one line
  // naming the path and the flag.
  PtyServer(boost::asio::io_context& io, PtyOptions options, SessionFactory factory);
  ~PtyServer();
  PtyServer(const PtyServer&) = delete;
  PtyServer& operator=(const PtyServer&) = delete;

  void start();              // watch for a program on the subordinate side
  void stop();               // close the connection, stop watching (the symlink stays until destruction)
  void close_connections();  // the current connection ends; watching goes on
  const std::string& subordinate() const { return subordinate_; }  // "/dev/pts/7"
  const std::string& link_path() const { return options_.link_path; }
  std::size_t connection_count() const { return connection_ ? 1 : 0; }

 private:
  class Stream;
  void arm();
  void check();
  void on_closed(LineConnectionBase* c);

  boost::asio::io_context& io_;
  PtyOptions options_;
  SessionFactory factory_;
  int master_ = -1;
  std::string subordinate_;
  boost::asio::steady_timer timer_;
  std::shared_ptr<LineConnectionBase> connection_;
  std::uint64_t next_id_ = 1;
  bool running_ = false;
  bool link_created_ = false;
};

}  // namespace mcemu::line::net
