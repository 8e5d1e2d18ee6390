// The RefGo and FAULHABER protocol rules (lint/link_rules.cpp): requests before replies, requests
// faster than the real drive answers, requests that race the statusword notification
// (docs/lint.md §4.4).
#include <gtest/gtest.h>

#include "lint_fixture.hpp"

namespace mcemu::lint::test {
namespace {

ProtocolRequest req(Ms t, Link link, Conn conn, std::uint64_t chunk = 0, bool expects = true) {
  return ProtocolRequest{t, link, conn, chunk, expects};
}
ProtocolReply reply(Ms t, Link link, Conn conn) { return ProtocolReply{t, link, conn, ReplyKind::response}; }
ProtocolReply notification(Ms t) { return ProtocolReply{t, Link::faulhaber, 0, ReplyKind::notification}; }

// ---- request before the reply

TEST(RefgoRequestBeforeReply, PipelinedLinesFire) {
  // the session observer sees every line of a read before any of them runs (refgo::Session)
  Lint l;
  l.engine.observe(req(100, Link::refgo, 7));
  l.engine.observe(req(100, Link::refgo, 7));
  l.engine.observe(reply(100, Link::refgo, 7));
  l.engine.observe(reply(100, Link::refgo, 7));
  ASSERT_TRUE(l.only(RuleId::refgo_request_before_reply));
  EXPECT_EQ(l.found.size(), 1U);
  EXPECT_EQ(l.found[0].conn, 7U);
  EXPECT_EQ(l.found[0].origin, "refgo");
}

TEST(RefgoRequestBeforeReply, QuietCases) {
  Lint l;
  l.engine.observe(req(100, Link::refgo, 7));
  l.engine.observe(req(100, Link::refgo, 8));  // another connection
  l.engine.observe(reply(101, Link::refgo, 7));
  l.engine.observe(reply(101, Link::refgo, 8));
  l.engine.observe(req(110, Link::refgo, 7));
  l.engine.observe(reply(110, Link::refgo, 7));
  l.engine.observe(req(120, Link::refgo, 7, 0, false));  // a line only the script gets
  l.engine.observe(req(130, Link::refgo, 7));
  EXPECT_TRUE(l.found.empty());
}

TEST(RefgoRequestBeforeReply, AReplyNeverReportedIsForgottenAfterTenSeconds) {
  Lint l;
  l.engine.observe(req(0, Link::refgo, 7));
  l.engine.observe(req(LinkRules::k_forget_ms, Link::refgo, 7));
  EXPECT_TRUE(l.found.empty());
}

TEST(FaulhaberRequestBeforeReply, RequestsOfOneReadFire) {
  // the FAULHABER port answers each frame before it decodes the next: only the read shows it
  Lint l;
  l.engine.observe(req(50, Link::faulhaber, 3, 9));
  l.engine.observe(reply(50, Link::faulhaber, 3));
  l.engine.observe(req(50, Link::faulhaber, 3, 9));
  l.engine.observe(reply(50, Link::faulhaber, 3));
  ASSERT_TRUE(l.only(RuleId::faulhaber_request_before_reply));
  EXPECT_NE(l.found[0].detail.find("same read"), std::string::npos);
}

TEST(FaulhaberRequestBeforeReply, HeldResponseFires) {
  // faulhaber.response_delay_ms holds the response: the host did not wait for it
  Lint l;
  l.engine.observe(req(50, Link::faulhaber, 3, 1));
  l.engine.observe(req(53, Link::faulhaber, 3, 2));
  EXPECT_TRUE(l.only(RuleId::faulhaber_request_before_reply));
}

TEST(FaulhaberRequestBeforeReply, OneRequestPerReadAfterTheReplyIsQuiet) {
  Lint l;
  for (std::uint64_t i = 1; i <= 5; ++i) {
    l.engine.observe(req(10 * i, Link::faulhaber, 3, i));
    l.engine.observe(reply(10 * i, Link::faulhaber, 3));
  }
  l.engine.observe(req(60, Link::faulhaber, 3, 6, false));  // for another node-id: no response
  l.engine.observe(ProtocolReply{60, Link::faulhaber, 3, ReplyKind::none});
  l.engine.observe(req(70, Link::faulhaber, 3, 7));
  EXPECT_TRUE(l.found.empty());
}

// ---- faster than the drive

TEST(FasterThanDrive, PollingFasterThanTheModelFires) {
  Lint l;
  l.engine.observe(req(100, Link::refgo, 7));
  l.engine.observe(reply(100, Link::refgo, 7));
  l.engine.observe(req(103, Link::refgo, 7));  // model: ≥ 4 ms
  l.engine.observe(reply(103, Link::refgo, 7));
  l.engine.observe(req(104, Link::faulhaber, 4, 1));
  l.engine.observe(reply(104, Link::faulhaber, 4));
  l.engine.observe(req(105, Link::faulhaber, 4, 2));  // model: ≥ 2 ms
  ASSERT_EQ(l.found.size(), 2U);
  EXPECT_EQ(l.found[0].rule, RuleId::refgo_faster_than_drive);
  EXPECT_EQ(l.found[0].severity, Severity::info);
  EXPECT_EQ(l.found[1].rule, RuleId::faulhaber_faster_than_drive);
}

TEST(FasterThanDrive, QuietCases) {
  Config c;
  c.faulhaber_min_response_ms = 0;  // off
  Lint l(c);
  l.engine.observe(req(100, Link::refgo, 7));
  l.engine.observe(reply(100, Link::refgo, 7));
  l.engine.observe(req(104, Link::refgo, 7));
  l.engine.observe(reply(104, Link::refgo, 7));
  l.engine.observe(req(105, Link::faulhaber, 4, 1));
  l.engine.observe(reply(105, Link::faulhaber, 4));
  l.engine.observe(req(105, Link::faulhaber, 4, 2));
  EXPECT_TRUE(l.found.empty());
}

TEST(FasterThanDrive, TimingOffForAManualClock) {
  Config c;
  c.timing = false;
  Lint l(c);
  l.engine.observe(req(0, Link::refgo, 7));
  l.engine.observe(reply(0, Link::refgo, 7));
  l.engine.observe(req(0, Link::refgo, 7));
  EXPECT_TRUE(l.found.empty());
  EXPECT_EQ(l.engine.counts(RuleId::refgo_faster_than_drive).occurrences, 0U);
}

// ---- FAULHABER: statusword notification ordering

// A controlword write by SDO over the FAULHABER port (origin sdo) that changes the statusword.
void cw_write(Lint& l, Ms t, std::uint16_t cw, std::uint16_t sw_after) {
  l.engine.observe(write(t, 0x6040, cw, sw_after, 0, od::Origin::sdo, 0));
}

TEST(FaulhaberRequestBeforeNotification, RequestInTheReadOfTheControlwordWriteFires) {
  Lint l;
  l.drive_at(0, 0x0040, 0);
  l.engine.observe(req(10, Link::faulhaber, 3, 1));
  cw_write(l, 10, 0x0006, 0x0021);
  l.engine.observe(reply(10, Link::faulhaber, 3));
  l.engine.observe(notification(10));
  l.engine.observe(req(10, Link::faulhaber, 3, 1));  // sent with the write, before the notification
  EXPECT_EQ(l.count(RuleId::faulhaber_request_before_notification), 1U);
  EXPECT_EQ(l.count(RuleId::faulhaber_request_before_reply), 1U);
}

TEST(FaulhaberRequestBeforeNotification, LateNotificationFiresAtTheRequest) {
  // a notification that comes after the host's next request (a port that lags notifications)
  Lint l;
  l.drive_at(0, 0x0040, 0);
  l.engine.observe(req(10, Link::faulhaber, 3, 1));
  cw_write(l, 10, 0x0006, 0x0021);
  l.engine.observe(reply(10, Link::faulhaber, 3));
  l.engine.observe(req(12, Link::faulhaber, 3, 2));
  EXPECT_TRUE(l.found.empty());
  l.engine.observe(notification(13));
  ASSERT_TRUE(l.only(RuleId::faulhaber_request_before_notification));
  EXPECT_EQ(l.found[0].time_ms, 12U);
  EXPECT_EQ(l.found[0].conn, 3U);
}

TEST(FaulhaberRequestBeforeNotification, QuietCases) {
  {  // waits for the notification
    Lint l;
    l.drive_at(0, 0x0040, 0);
    l.engine.observe(req(10, Link::faulhaber, 3, 1));
    cw_write(l, 10, 0x0006, 0x0021);
    l.engine.observe(reply(10, Link::faulhaber, 3));
    l.engine.observe(notification(10));
    l.engine.observe(req(15, Link::faulhaber, 3, 2));
    EXPECT_TRUE(l.found.empty());
  }
  {  // a controlword that changes nothing causes no notification
    Lint l;
    l.drive_at(0, 0x0040, 0);
    l.engine.observe(req(10, Link::faulhaber, 3, 1));
    cw_write(l, 10, 0x0000, 0x0040);
    l.engine.observe(reply(10, Link::faulhaber, 3));
    l.engine.observe(req(15, Link::faulhaber, 3, 2));
    l.engine.observe(notification(20));  // the drive's own change later
    EXPECT_TRUE(l.found.empty());
  }
  {  // notifications off (0x2400.04 bit 17 clear): none ever comes, nothing is reported
    Lint l;
    l.drive_at(0, 0x0040, 0);
    l.engine.observe(req(10, Link::faulhaber, 3, 1));
    cw_write(l, 10, 0x0006, 0x0021);
    l.engine.observe(reply(10, Link::faulhaber, 3));
    for (std::uint64_t i = 2; i < 10; ++i) {
      l.engine.observe(req(10 * i, Link::faulhaber, 3, i));
      l.engine.observe(reply(10 * i, Link::faulhaber, 3));
    }
    EXPECT_TRUE(l.found.empty());
  }
  {  // RefGo writes of 6040h never wait for notifications
    Lint l;
    l.drive_at(0, 0x0040, 0);
    l.engine.observe(req(10, Link::refgo, 3));
    l.engine.observe(write(10, 0x6040, 6, 0x0021, 0, od::Origin::refgo, 3));
    l.engine.observe(reply(10, Link::refgo, 3));
    l.engine.observe(req(20, Link::refgo, 3));
    l.engine.observe(notification(21));
    EXPECT_TRUE(l.found.empty());
  }
}

TEST(LinkSlots, ClosedConnectionForgetsItsOutstandingRequest) {
  Lint l;
  l.engine.observe(req(0, Link::refgo, 7));
  l.engine.observe(ConnectionClosed{7});
  l.engine.observe(req(100, Link::refgo, 7));
  EXPECT_TRUE(l.found.empty());
}

TEST(LinkSlots, ManyConnectionsReuseTheOldestSlot) {
  Lint l;
  for (Conn c = 1; c <= 3 * LinkRules::k_slots; ++c) l.engine.observe(req(c * 10, Link::refgo, c));
  // the first connections were evicted: their slots start fresh
  l.engine.observe(req(1000, Link::refgo, 1));
  EXPECT_TRUE(l.found.empty());
  // the most recent one still knows its outstanding request
  l.engine.observe(req(1000, Link::refgo, 3 * LinkRules::k_slots));
  EXPECT_TRUE(l.only(RuleId::refgo_request_before_reply));
}

}  // namespace
}  // namespace mcemu::lint::test
