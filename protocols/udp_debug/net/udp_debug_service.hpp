// The Asio side of the UDP debug console (udp-debug.md §1, §3.4, §5.2): the receive loop, the one
// posted flush per burst of output, non-blocking sends from the bound socket, and the counters.
//
// Contract: everything on the io_context's single thread. The socket is bound by the composition
// root (server/drive_unit.cpp, one per MovingCap drive) and outlives the service. Sending never blocks: a datagram the
// kernel refuses is dropped and counted; a receive error is counted and the next receive starts at once. The
// composition root calls power_up() at process start and power_cycle() for a power cycle (listeners and backlog
// forgotten, start-up block produced again, persistence.md §7). Taps (udp-debug.md §6, web.md §9, morse-led.md §5.2),
// through Taps: the time stamp of a registration, every datagram received (with the console's verdict) and sent, and a
// veto per datagram before it is sent (udp.drop: counted as dropped, not sent).
#pragma once

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <string_view>

#include "protocols/udp_debug/console.hpp"

namespace mcemu::udp_debug::net {

struct Counters {
  std::uint64_t datagrams_sent = 0;
  std::uint64_t datagrams_dropped = 0;  // refused by the kernel
  std::uint64_t datagrams_received = 0;
  std::uint64_t receive_errors = 0;
};

class UdpDebugService {
 public:
  struct Taps {
    std::function<Stamp()> now;  // drive and wall time of a received datagram
    std::function<void(const Peer& from, std::string_view payload, Console::Received r)> received;
    std::function<bool(const Datagram& d)> may_send;  // false: not sent (counted as dropped)
    std::function<void(const Datagram& d)> sent;
  };

  UdpDebugService(boost::asio::io_context& io, boost::asio::ip::udp::socket& socket);
  ~UdpDebugService();
  UdpDebugService(const UdpDebugService&) = delete;
  UdpDebugService& operator=(const UdpDebugService&) = delete;

  void start();  // begin receiving
  void stop();   // stop receiving and sending (the socket stays open)

  // One console message (with its own line ending).
  void emit(std::string message);
  // An emulator note "mcemu: <text>\r\n", sent only while notes are on (udp-debug.md §4.7).
  void note(std::string_view text);
  void set_notes(bool on) { notes_ = on; }
  void set_taps(Taps taps) { taps_ = std::move(taps); }
  bool notes() const { return notes_; }

  // The start-up block of a power-up (udp-debug.md §4.1).
  void power_up(std::string_view ip, std::string_view script_id);
  // Forget listeners, backlog and unsent output, then produce the start-up block again.
  void power_cycle(std::string_view ip, std::string_view script_id);

  const Console& console() const { return console_; }
  const Counters& counters() const { return counters_; }
  // Every console message as it is produced, whether or not a listener is registered (the
  // WebSocket channel "udp", udp-debug.md §6), and the last k_history of them (GET /api/v1/udp).
  void set_message_listener(std::function<void(const std::string&)> listener) { listener_ = std::move(listener); }
  static constexpr std::size_t k_history = 500;
  const std::deque<std::string>& history() const { return history_; }

 private:
  void remember(const std::string& message);
  void do_receive();
  void on_receive(const boost::system::error_code& ec, std::size_t n);
  void schedule_flush();
  void flush();

  boost::asio::io_context& io_;
  boost::asio::ip::udp::socket& socket_;
  Console console_;
  Counters counters_;
  std::array<char, 2048> buffer_{};
  boost::asio::ip::udp::endpoint sender_;
  std::function<void(const std::string&)> listener_;
  Taps taps_;
  std::deque<std::string> history_;
  bool notes_ = false;
  bool running_ = false;
  bool flush_posted_ = false;
  std::uint64_t generation_ = 0;  // a power cycle or stop invalidates a posted flush
};

}  // namespace mcemu::udp_debug::net
