#include "protocols/udp_debug/net/udp_debug_service.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/buffer.hpp>
#include <boost/asio/post.hpp>

#include "protocols/udp_debug/messages.hpp"

namespace mcemu::udp_debug::net {

namespace asio = boost::asio;
using udp = asio::ip::udp;

namespace {
Peer peer_of(const udp::endpoint& e) { return {e.address().to_string(), e.port()}; }
}  // namespace

UdpDebugService::UdpDebugService(asio::io_context& io, udp::socket& socket) : io_(io), socket_(socket) {
  boost::system::error_code ec;
  socket_.non_blocking(true, ec);
  const auto own = socket_.local_endpoint(ec);
  if (!ec) console_.set_own(peer_of(own));
}

UdpDebugService::~UdpDebugService() { stop(); }

void UdpDebugService::start() {
  if (running_) return;
  running_ = true;
  do_receive();
  schedule_flush();
}

void UdpDebugService::stop() {
  running_ = false;
  ++generation_;
  flush_posted_ = false;
  boost::system::error_code ec;
  if (socket_.is_open()) socket_.cancel(ec);
}

void UdpDebugService::emit(std::string message) {
  remember(message);
  console_.emit(std::move(message));
  schedule_flush();
}

void UdpDebugService::remember(const std::string& message) {
  if (history_.size() == k_history) history_.pop_front();
  history_.push_back(message);
  if (listener_) listener_(message);
}

void UdpDebugService::note(std::string_view text) {
  if (notes_) emit(udp_debug::note(text));
}

void UdpDebugService::power_up(std::string_view ip, std::string_view script_id) {
  for (auto& m : startup_block(ip, script_id)) {
    remember(m);
    console_.emit(std::move(m));
  }
  schedule_flush();
}

void UdpDebugService::power_cycle(std::string_view ip, std::string_view script_id) {
  // The note reaches the listeners of the old power-up; the start-up block stays the first
  // message of the new one.
  note("power cycle");
  flush();
  console_.forget_all();
  ++generation_;
  flush_posted_ = false;
  power_up(ip, script_id);
}

void UdpDebugService::do_receive() {
  if (!running_ || !socket_.is_open()) return;
  socket_.async_receive_from(asio::buffer(buffer_), sender_,
                             [this](const boost::system::error_code& ec, std::size_t n) { on_receive(ec, n); });
}

void UdpDebugService::on_receive(const boost::system::error_code& ec, std::size_t n) {
  if (ec == asio::error::operation_aborted || !running_) return;
  if (ec) {
    // ICMP port unreachable from an earlier send shows up here on Linux; it never stops the loop.
    ++counters_.receive_errors;
  } else {
    ++counters_.datagrams_received;
    const Peer from = peer_of(sender_);
    const std::string_view payload(buffer_.data(), n);
    const auto r = console_.on_datagram(from, payload, taps_.now ? taps_.now() : Stamp{});
    if (taps_.received) taps_.received(from, payload, r);
    if (r == Console::Received::registered) {
      spdlog::debug("udp: listener {}:{} registered", from.address, from.port);
      schedule_flush();
    }
  }
  do_receive();
}

void UdpDebugService::schedule_flush() {
  if (!running_ || flush_posted_ || !console_.has_output()) return;
  flush_posted_ = true;
  asio::post(io_, [this, gen = generation_] {
    if (gen != generation_) return;
    flush_posted_ = false;
    flush();
  });
}

void UdpDebugService::flush() {
  if (!running_) return;
  for (const auto& d : console_.take_datagrams()) {
    if (taps_.may_send && !taps_.may_send(d)) {
      ++counters_.datagrams_dropped;
      continue;
    }
    boost::system::error_code ec;
    const auto address = asio::ip::make_address(d.to.address, ec);
    if (!ec) socket_.send_to(asio::buffer(d.payload), udp::endpoint(address, d.to.port), 0, ec);
    if (ec) {
      ++counters_.datagrams_dropped;
    } else {
      ++counters_.datagrams_sent;
      if (taps_.sent) taps_.sent(d);
    }
  }
}

}  // namespace mcemu::udp_debug::net
