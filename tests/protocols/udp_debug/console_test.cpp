// The UDP console without a socket: registration, backlog, listeners, packing and the start-up
// block (udp-debug.md §2–§5, vectors §7.1, §7.5, §7.6).
#include "protocols/udp_debug/console.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "protocols/udp_debug/messages.hpp"

namespace mcemu::udp_debug {
namespace {

const Peer k_a{"127.0.0.1", 40001};
const Peer k_b{"127.0.0.1", 40002};
const Peer k_c{"127.0.0.1", 40003};
const Peer k_d{"127.0.0.1", 40004};
const Peer k_e{"127.0.0.1", 40005};

std::vector<std::string> payloads(std::vector<Datagram> ds, const Peer& to) {
  std::vector<std::string> out;
  for (auto& d : ds) {
    if (d.to == to) out.push_back(std::move(d.payload));
  }
  return out;
}

TEST(Registration, OnlyCrLfPayloadsOfOneToFourBytes) {
  for (const char* ok : {"\r", "\n", "\r\n", "\n\r", "\r\r\r\r", "\n\n\n\n"}) EXPECT_TRUE(is_registration(ok)) << ok;
  for (const char* bad : {"", "\r\r\r\r\r", "x", "\r ", " \r", "TP\r", ">\r\n"}) {
    EXPECT_FALSE(is_registration(bad)) << bad;
  }
}

// §7.1: the first registration after power-up receives the start-up block, "\r" and ">\r\n" in
// one datagram of 275 bytes.
TEST(Console, StartupReplayIsOneDatagramOf275Bytes) {
  Console c;
  for (auto& m : startup_block("192.168.2.150", "maxTRACK N23 demo rev8")) c.emit(std::move(m));
  EXPECT_FALSE(c.has_output());
  EXPECT_EQ(c.on_datagram(k_a, "\r"), Console::Received::registered);
  const auto ds = c.take_datagrams();
  ASSERT_EQ(ds.size(), 1U);
  EXPECT_EQ(ds[0].to, k_a);
  EXPECT_EQ(ds[0].payload,
            "SYS_Initialize: The MPFS2 File System is mounted\r\n"
            "TCP/IP Stack: Initialization Ended - success \n\r"
            "Host MOVINGCAP TCP   - NBNS disabled\r\n"
            "IP Address: 192.168.2.150 \r\n"
            "REFGO - opening server\r\n"
            "code: starting upload...\r\n"
            "code: upload complete, script id: maxTRACK N23 demo rev8\r\n"
            "\r"
            ">\r\n");
  EXPECT_EQ(ds[0].payload.size(), 275U);
  // A second "\r" from the same port yields exactly "\r>\r\n".
  c.on_datagram(k_a, "\r");
  const auto again = c.take_datagrams();
  ASSERT_EQ(again.size(), 1U);
  EXPECT_EQ(again[0].payload, "\r>\r\n");
  EXPECT_EQ(c.listeners().size(), 1U);
}

TEST(Console, RegistrationEchoesItsOwnBytes) {
  Console c;
  c.on_datagram(k_a, "\n");
  EXPECT_EQ(payloads(c.take_datagrams(), k_a), std::vector<std::string>{"\n>\r\n"});
  c.on_datagram(k_b, "\r\n");
  EXPECT_EQ(payloads(c.take_datagrams(), k_b), std::vector<std::string>{"\r\n>\r\n"});
}

TEST(Console, OtherPayloadsAndOwnDatagramsAreIgnored) {
  Console c;
  c.set_own(k_e);
  EXPECT_EQ(c.on_datagram(k_a, "hello"), Console::Received::ignored);
  EXPECT_EQ(c.on_datagram(k_a, ">\r\n"), Console::Received::ignored);
  EXPECT_EQ(c.on_datagram(k_e, "\r"), Console::Received::own);
  EXPECT_FALSE(c.has_output());
  EXPECT_TRUE(c.listeners().empty());
  EXPECT_EQ(c.ignored(), 2U);
}

// §7.5: 2000 ten-byte messages with nobody listening keep the last 819 (8190 bytes); the
// registration gets them in 8 datagrams of 1020 bytes and one of 34.
TEST(Console, BacklogKeepsTheNewestWholeMessages) {
  Console c;
  for (auto& m : startup_block("192.168.2.150", "(empty)")) c.emit(std::move(m));
  for (int i = 0; i < 2000; ++i) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%08d\r\n", i);
    c.emit(buf);
  }
  EXPECT_EQ(c.backlog_messages(), 819U);
  EXPECT_EQ(c.backlog_bytes(), 8190U);
  c.on_datagram(k_a, "\r");
  const auto ds = payloads(c.take_datagrams(), k_a);
  ASSERT_EQ(ds.size(), 9U);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(ds[static_cast<std::size_t>(i)].size(), 1020U);
  EXPECT_EQ(ds[8].size(), 34U);
  EXPECT_EQ(ds[0].substr(0, 10), "00001181\r\n");
  EXPECT_EQ(ds[8], "00001997\r\n00001998\r\n00001999\r\n\r>\r\n");
  EXPECT_EQ(c.backlog_bytes(), 0U);
}

TEST(Console, OneHugeMessageKeepsItsLast8192Bytes) {
  Console c;
  c.emit("first\r\n");
  std::string big(10000, 'x');
  big.replace(big.size() - 4, 4, "END\n");
  c.emit(big);
  EXPECT_EQ(c.backlog_messages(), 1U);
  EXPECT_EQ(c.backlog_bytes(), 8192U);
  c.emit("next\r\n");  // drops the big one to fit
  EXPECT_EQ(c.backlog_messages(), 1U);
  EXPECT_EQ(c.backlog_bytes(), 6U);
}

TEST(Console, LiveOutputGoesToEveryListenerNotTheBacklog) {
  Console c;
  c.on_datagram(k_a, "\r");
  c.on_datagram(k_b, "\r");
  (void)c.take_datagrams();
  c.emit("Hello World from MovingCap!\r\n");
  c.emit("second\r\n");
  const auto ds = c.take_datagrams();
  EXPECT_EQ(payloads(ds, k_a), std::vector<std::string>{"Hello World from MovingCap!\r\nsecond\r\n"});
  EXPECT_EQ(payloads(ds, k_b), std::vector<std::string>{"Hello World from MovingCap!\r\nsecond\r\n"});
  EXPECT_EQ(c.backlog_bytes(), 0U);
}

// §7.6: four listeners; a fifth evicts the one whose latest registration is the oldest.
TEST(Console, FifthListenerEvictsTheOldestRegistration) {
  Console c;
  for (const auto& p : {k_a, k_b, k_c, k_d}) c.on_datagram(p, "\r");
  (void)c.take_datagrams();
  c.emit("x\r\n");
  EXPECT_EQ(c.take_datagrams().size(), 4U);
  c.on_datagram(k_e, "\r");
  ASSERT_EQ(c.listeners().size(), 4U);
  for (const auto& l : c.listeners()) EXPECT_NE(l.peer, k_a);
  (void)c.take_datagrams();

  Console d;
  for (const auto& p : {k_a, k_b, k_c, k_d}) d.on_datagram(p, "\r");
  d.on_datagram(k_a, "\r");  // re-registration makes A the newest
  d.on_datagram(k_e, "\r");
  ASSERT_EQ(d.listeners().size(), 4U);
  for (const auto& l : d.listeners()) EXPECT_NE(l.peer, k_b);
  const auto ds = d.take_datagrams();
  EXPECT_TRUE(payloads(ds, k_b).empty());  // queued output of an evicted listener is not sent
  EXPECT_EQ(payloads(ds, k_e), std::vector<std::string>{"\r>\r\n"});
}

TEST(Console, ForgetAllIsAPowerCycle) {
  Console c;
  c.on_datagram(k_a, "\r");
  c.emit("pending\r\n");
  c.forget_all();
  EXPECT_FALSE(c.has_output());
  EXPECT_TRUE(c.listeners().empty());
  c.emit("after\r\n");
  EXPECT_EQ(c.backlog_messages(), 1U);
}

TEST(Pack, WholeMessagesUpTo1024AndPiecesOfLongOnes) {
  std::vector<std::string> ms{std::string(600, 'a'), std::string(600, 'b'), std::string(424, 'c')};
  auto ds = pack(ms);
  ASSERT_EQ(ds.size(), 2U);
  EXPECT_EQ(ds[0], std::string(600, 'a'));
  EXPECT_EQ(ds[1], std::string(600, 'b') + std::string(424, 'c'));

  ms = {"head\r\n", std::string(2500, 'x'), "tail\r\n"};
  ds = pack(ms);
  ASSERT_EQ(ds.size(), 4U);
  EXPECT_EQ(ds[0], "head\r\n");
  EXPECT_EQ(ds[1], std::string(1024, 'x'));
  EXPECT_EQ(ds[2], std::string(1024, 'x'));
  EXPECT_EQ(ds[3], std::string(452, 'x') + "tail\r\n");

  ms = {std::string(1024, 'y'), "z"};
  ds = pack(ms);
  ASSERT_EQ(ds.size(), 2U);
  EXPECT_EQ(ds[0].size(), 1024U);
  EXPECT_EQ(ds[1], "z");
  EXPECT_TRUE(pack({}).empty());
}

TEST(Messages, NoteAndUpload) {
  EXPECT_EQ(note("fault cleared"), "mcemu: fault cleared\r\n");
  EXPECT_EQ(note(fault_text(0x7121)), "mcemu: fault 7121h ERROR_STROKE\r\n");
  EXPECT_EQ(fault_text(0xFFF2), "fault FFF2h ERROR_HW_SW_ENABLE");
  EXPECT_EQ(fault_text(0x1234), "fault 1234h UNKNOWN");
  const auto up = upload_messages("(empty)");
  ASSERT_EQ(up.size(), 2U);
  EXPECT_EQ(up[1], "code: upload complete, script id: (empty)\r\n");
}

}  // namespace
}  // namespace mcemu::udp_debug

namespace mcemu::udp_debug {
namespace {

TEST(Console, ListenersKeepTheTimeOfTheirLatestRegistration) {  // udp-debug.md §6
  Console c;
  c.on_datagram(k_a, "\r", Stamp{100, "2026-01-15T10:15:02.100Z"});
  c.on_datagram(k_b, "\r", Stamp{150, "2026-01-15T10:15:02.150Z"});
  c.on_datagram(k_a, "\n", Stamp{900, "2026-01-15T10:15:02.900Z"});
  c.on_datagram(k_b, "hello", Stamp{950, "x"});  // ignored: no new registration time
  ASSERT_EQ(c.listeners().size(), 2u);
  EXPECT_EQ(c.listeners()[0].peer, k_a);
  EXPECT_EQ(c.listeners()[0].registered.drive_ms, 900u);
  EXPECT_EQ(c.listeners()[0].registered.wall, "2026-01-15T10:15:02.900Z");
  EXPECT_EQ(c.listeners()[1].registered.drive_ms, 150u);
}

}  // namespace
}  // namespace mcemu::udp_debug
