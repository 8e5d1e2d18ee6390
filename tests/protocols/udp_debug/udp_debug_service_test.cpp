// The Asio UDP service on 127.0.0.1 with real sockets: answers from the bound port, one posted
// flush per burst, over-long messages in 1024-byte pieces, and the power-cycle API.
#include "protocols/udp_debug/net/udp_debug_service.hpp"

#include <gtest/gtest.h>

#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <optional>

#include "protocols/udp_debug/messages.hpp"

namespace mcemu::udp_debug::net {
namespace {

namespace asio = boost::asio;
using udp = asio::ip::udp;

class ServiceTest : public ::testing::Test {
 protected:
  ServiceTest() : server_(io_, udp::endpoint(asio::ip::make_address("127.0.0.1"), 0)), client_(io_) {
    client_.open(udp::v4());
    client_.bind(udp::endpoint(asio::ip::make_address("127.0.0.1"), 0));
    client_.non_blocking(true);
    service_.emplace(io_, server_);
    service_->start();
  }

  udp::endpoint server_endpoint() const { return server_.local_endpoint(); }
  void send(std::string_view payload) { client_.send_to(asio::buffer(payload), server_endpoint()); }

  // Runs the loop until a datagram arrives at the client (bounded), or returns nullopt.
  std::optional<std::pair<std::string, udp::endpoint>> receive(
      std::chrono::milliseconds limit = std::chrono::seconds(5)) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    std::array<char, 4096> buf{};
    udp::endpoint from;
    while (std::chrono::steady_clock::now() < deadline) {
      io_.poll();
      io_.restart();
      boost::system::error_code ec;
      const auto n = client_.receive_from(asio::buffer(buf), from, 0, ec);
      if (!ec) return std::make_pair(std::string(buf.data(), n), from);
      io_.run_for(std::chrono::milliseconds(1));
      io_.restart();
    }
    return std::nullopt;
  }

  asio::io_context io_;
  udp::socket server_;
  udp::socket client_;
  std::optional<UdpDebugService> service_;
};

TEST_F(ServiceTest, BootLogToTheRegisteringPortFromTheBoundPort) {
  service_->power_up("192.168.2.150", "(empty)");
  send("\r");
  const auto d = receive();
  ASSERT_TRUE(d);
  std::string expected;
  for (const auto& m : startup_block("192.168.2.150", "(empty)")) expected += m;
  EXPECT_EQ(d->first, expected + "\r>\r\n");
  EXPECT_EQ(d->second, server_endpoint());
  EXPECT_EQ(service_->console().listeners().size(), 1U);
  EXPECT_EQ(service_->counters().datagrams_sent, 1U);
}

TEST_F(ServiceTest, OneBurstSharesDatagramsAndLongMessagesArePieces) {
  send("\r");
  ASSERT_TRUE(receive());
  service_->emit("a\r\n");
  service_->emit("b\r\n");
  auto d = receive();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->first, "a\r\nb\r\n");
  service_->emit(std::string(3000, 'x'));
  std::vector<std::size_t> sizes;
  for (int i = 0; i < 3; ++i) {
    d = receive();
    ASSERT_TRUE(d);
    sizes.push_back(d->first.size());
  }
  EXPECT_EQ(sizes, (std::vector<std::size_t>{1024, 1024, 952}));
}

TEST_F(ServiceTest, NotesOnlyWhenEnabled) {
  send("\r");
  ASSERT_TRUE(receive());
  service_->note("fault cleared");
  EXPECT_FALSE(receive(std::chrono::milliseconds(100)));
  service_->set_notes(true);
  service_->note("fault cleared");
  const auto d = receive();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->first, "mcemu: fault cleared\r\n");
}

TEST_F(ServiceTest, PowerCycleForgetsListenersAndProducesTheStartupBlockAgain) {
  service_->power_up("192.168.2.150", "(empty)");
  send("\r");
  ASSERT_TRUE(receive());
  service_->set_notes(true);
  service_->power_cycle("10.0.0.7", "demo");
  auto d = receive();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->first, "mcemu: power cycle\r\n");  // the old listener hears the power cycle
  EXPECT_TRUE(service_->console().listeners().empty());
  service_->emit("later\r\n");  // nobody listens: backlog
  EXPECT_FALSE(receive(std::chrono::milliseconds(100)));
  send("\r");
  d = receive();
  ASSERT_TRUE(d);
  std::string expected;
  for (const auto& m : startup_block("10.0.0.7", "demo")) expected += m;
  EXPECT_EQ(d->first, expected + "later\r\n\r>\r\n");
}

TEST_F(ServiceTest, IgnoredPayloadsAreCountedNotAnswered) {
  send("hello");
  send("TP\r");
  EXPECT_FALSE(receive(std::chrono::milliseconds(100)));
  EXPECT_EQ(service_->console().ignored(), 2U);
  EXPECT_EQ(service_->counters().datagrams_received, 2U);
}

}  // namespace
}  // namespace mcemu::udp_debug::net
