// A script attached to port 10001 (refgo.md §5, §15.8): the dispatch of modes 1, 2, 3 through real
// sessions, lines given to the script (original case), the 64-line queue, the reply target of
// refgo.write, and detaching.
#include "protocols/refgo/attachment.hpp"

#include <gtest/gtest.h>

#include "protocols/refgo/session.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::refgo {
namespace {

TEST(AttachmentRoute, Table) {
  EXPECT_TRUE(route(AttachMode::none, false, false).execute);
  EXPECT_FALSE(route(AttachMode::none, false, false).forward);
  for (const bool known : {false, true}) {
    EXPECT_TRUE(route(AttachMode::forward_all, false, known).execute);
    EXPECT_TRUE(route(AttachMode::forward_all, false, known).forward);
    EXPECT_FALSE(route(AttachMode::script_only, false, known).execute);
    EXPECT_TRUE(route(AttachMode::script_only, false, known).forward);
  }
  EXPECT_TRUE(route(AttachMode::forward_unprocessed, false, true).execute);
  EXPECT_FALSE(route(AttachMode::forward_unprocessed, false, true).forward);
  EXPECT_FALSE(route(AttachMode::forward_unprocessed, false, false).execute);
  EXPECT_TRUE(route(AttachMode::forward_unprocessed, false, false).forward);
  EXPECT_TRUE(route(AttachMode::forward_unprocessed, true, true).execute);
  EXPECT_TRUE(route(AttachMode::script_only, true, true).forward);
}

class AttachmentTest : public ::testing::Test {
 protected:
  test::Drive d_;
  Attachment& a_ = d_.in.attachment();
};

TEST_F(AttachmentTest, ModeOneForwardsAfterTheBuiltInReply) {
  Session s(d_.in);
  a_.open(AttachMode::forward_all);
  s.receive("tp\rEVT1\r");
  EXPECT_TRUE(test::matches_vector(s.take_output(), "TP\r\n{TP}\r\n>>"));
  EXPECT_EQ(a_.read(), "tp");
  EXPECT_EQ(a_.read(), "EVT1");
  EXPECT_FALSE(a_.read());
}

TEST_F(AttachmentTest, ModeTwoForwardsOnlyUnknownWords) {
  Session s(d_.in);
  a_.open(AttachMode::forward_unprocessed);
  s.receive("TT\r\rTS\r");
  EXPECT_EQ(s.take_output(), ">TS\r\n0\r\n>");  // nothing for TT, '>' for the empty line
  EXPECT_EQ(a_.read(), "TT");
  EXPECT_FALSE(a_.read());
  EXPECT_TRUE(a_.write("TT\r\n125\r\n>"));
  EXPECT_EQ(s.take_output(), "TT\r\n125\r\n>");
}

TEST_F(AttachmentTest, ModeThreeDisablesTheInterpreter) {
  Session s(d_.in);
  a_.open(AttachMode::script_only);
  s.receive("G1000\r\r");
  EXPECT_EQ(s.take_output(), "");
  EXPECT_EQ(a_.read(), "G1000");
  EXPECT_EQ(a_.read(), "");
  EXPECT_EQ(d_.get(0x607A), 0);  // not executed
}

TEST_F(AttachmentTest, OverlongLinesAreAnsweredInEveryMode) {
  Session s(d_.in);
  a_.open(AttachMode::script_only);
  s.receive(std::string(300, 'A') + "\r");
  EXPECT_EQ(s.take_output(), ">");
  EXPECT_EQ(a_.waiting(), 0U);
}

TEST_F(AttachmentTest, WriteGoesToTheLastReadConnectionOrToAll) {
  Session one(d_.in);
  Session two(d_.in);
  a_.open(AttachMode::script_only);
  EXPECT_TRUE(a_.write("@H"));  // nothing read since open: every client
  EXPECT_EQ(one.take_output(), "@H");
  EXPECT_EQ(two.take_output(), "@H");
  two.receive("X\r");
  ASSERT_EQ(a_.read(), "X");
  EXPECT_TRUE(a_.write(">"));
  EXPECT_EQ(one.take_output(), "");
  EXPECT_EQ(two.take_output(), ">");
}

TEST_F(AttachmentTest, WriteToAClosedConnectionFails) {
  auto s = std::make_unique<Session>(d_.in);
  a_.open(AttachMode::script_only);
  s->receive("X\r");
  ASSERT_EQ(a_.read(), "X");
  s.reset();
  EXPECT_FALSE(a_.write(">"));
  a_.open(AttachMode::script_only);
  EXPECT_FALSE(a_.write(">"));  // no client at all
}

TEST_F(AttachmentTest, AtMost64LinesWait) {
  Session s(d_.in);
  a_.open(AttachMode::script_only);
  for (int i = 0; i < 70; ++i) {
    std::string line = "L";
    line += std::to_string(i);
    line += '\r';
    s.receive(line);
  }
  EXPECT_EQ(a_.waiting(), 64U);
  EXPECT_EQ(a_.dropped(), 6U);
  EXPECT_EQ(a_.read(), "L0");
}

TEST_F(AttachmentTest, CloseDetachesAndDropsLines) {
  Session s(d_.in);
  a_.open(AttachMode::script_only);
  s.receive("X\r");
  a_.close();
  EXPECT_FALSE(a_.attached());
  EXPECT_FALSE(a_.read());
  EXPECT_FALSE(a_.write(">"));
  s.receive("XYZ\r");
  EXPECT_EQ(s.take_output(), ">");  // the built-in interpreter is back
}

TEST(AttachmentRegistration, OutlivingTheAttachmentIsSafe) {
  auto a = std::make_unique<Attachment>();
  int calls = 0;
  auto r = a->add_connection([&](std::string_view) { ++calls; });
  EXPECT_EQ(a->connections(), 1U);
  a.reset();
  r.reset();  // points at a dead attachment: nothing happens
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace mcemu::refgo
