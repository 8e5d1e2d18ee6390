// The RefGo connection session (refgo.md §1.5, §2, §3): framing, one reply per line in order,
// over-long lines, a pending Store holding back later lines, FIN handling; every input split at
// every byte offset gives the same bytes.
#include "protocols/refgo/session.hpp"

#include <gtest/gtest.h>

#include "protocols/refgo/interpreter.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::refgo {
namespace {

class SessionTest : public ::testing::Test {
 protected:
  // Fixed status values (the core would only change them at its next step, never taken here).
  SessionTest() {
    od_.write(0x6064, 0, od::Value{std::int64_t{-7200}}, od::Origin::internal);
    od_.write(0x6041, 0, od::Value{std::int64_t{0x0427}}, od::Origin::internal);
  }

  // Feeds `input` in pieces cut at `cuts` and returns everything the session queued.
  std::string feed_split(const std::string& input, const std::vector<std::size_t>& cuts) {
    Session s(in_);
    std::string out;
    std::size_t from = 0;
    for (std::size_t cut : cuts) {
      s.receive(std::string_view(input).substr(from, cut - from));
      out += s.take_output();
      from = cut;
    }
    s.receive(std::string_view(input).substr(from));
    out += s.take_output();
    return out;
  }

  test::Drive d_;
  od::ObjectDictionary& od_ = d_.od;
  Interpreter& in_ = d_.in;
};

struct StreamCase {
  const char* name;
  std::string input;
  std::string output;
};

class Streams : public SessionTest, public ::testing::WithParamInterface<StreamCase> {};

TEST_P(Streams, SameBytesForEverySplit) {
  const auto& c = GetParam();
  EXPECT_EQ(feed_split(c.input, {}), c.output);
  for (std::size_t cut = 0; cut <= c.input.size(); ++cut) {
    ASSERT_EQ(feed_split(c.input, {cut}), c.output) << "cut at " << cut;
  }
  std::vector<std::size_t> every;
  for (std::size_t i = 1; i < c.input.size(); ++i) every.push_back(i);
  EXPECT_EQ(feed_split(c.input, every), c.output) << "byte by byte";
}

const std::string k_300a(300, 'A');
const std::string k_255 = "OR6064,0" + std::string(247, ' ');

INSTANTIATE_TEST_SUITE_P(
    Framing, Streams,
    ::testing::Values(StreamCase{"cr", "TP\r", "TP\r\n-7200\r\n>"},
                      StreamCase{"crlf_one_reply", "TP\r\n", "TP\r\n-7200\r\n>"},
                      StreamCase{"lf", "TP\n", "TP\r\n-7200\r\n>"},
                      StreamCase{"lfcr_two_lines", "TP\n\r", "TP\r\n-7200\r\n>>"},
                      StreamCase{"lower_case", "tp\r", "TP\r\n-7200\r\n>"}, StreamCase{"bare_cr", "\r", ">"},
                      StreamCase{"spaces", "  \r", ">"}, StreamCase{"unknown", "XYZ\r", ">"},
                      StreamCase{"tab_becomes_space", "SO\t7\r", "SO 7\r\nSO 7,ERROR,06090030h\r\n>"},
                      StreamCase{"controls_removed", std::string("T\x01P\x7F\x00\r", 6), "TP\r\n-7200\r\n>"},
                      StreamCase{"telnet_cr_nul", std::string("TP\r\0TS\r\0", 8), "TP\r\n-7200\r\n>TS\r\n1\r\n>"},
                      StreamCase{"overlong", k_300a + "\r", ">"},
                      StreamCase{"overlong_then_next", k_300a + "\rTP\r", ">TP\r\n-7200\r\n>"},
                      StreamCase{"exactly_255_executes", k_255 + "\r", k_255 + "\r\nOR6064,0,-7200\r\n>"},
                      StreamCase{"256_is_overlong", k_255 + " \r", ">"},
                      StreamCase{"unterminated_rest_waits", "TP\rTS", "TP\r\n-7200\r\n>"},
                      StreamCase{"mixed_terminators", "TP\rTS\nTPSR\r\nOR6041,0,h\n\r",
                                 "TP\r\n-7200\r\n>TS\r\n1\r\n>TPSR\r\n0000010a\r\n>OR6041,0,H\r\nOR6041,0,427h\r\n>>"},
                      StreamCase{"binary_garbage_then_valid", std::string("\xFF\xFE\x00\x80GARBAGE\x1B[2J\rTP\r", 19),
                                 ">TP\r\n-7200\r\n>"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST_F(SessionTest, HundredPipelinedLinesInOrder) {
  Session s(in_);
  std::string input;
  std::string expected;
  for (int i = 0; i < 100; ++i) {
    input += "OW3410,1," + std::to_string(i) + (i % 3 == 0 ? "\r" : i % 3 == 1 ? "\n" : "\r\n");
    input += "OR3410,1\r";
    expected += "OW3410,1," + std::to_string(i) + "\r\nOW3410,1," + std::to_string(i) + ",OK\r\n>";
    expected += "OR3410,1\r\nOR3410,1," + std::to_string(i) + "\r\n>";
  }
  s.receive(input);
  EXPECT_EQ(s.take_output(), expected);
}

TEST_F(SessionTest, PendingStoreHoldsBackLaterLines) {
  od::Done held;
  d_.release_store_hooks();  // this test's hook stands in for the persistence service
  od_.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  Session s(in_);
  int wakes = 0;
  s.set_wake([&] { ++wakes; });
  s.receive("TP\rOW1010,1,1702257011\rTS\rTP\r");
  EXPECT_EQ(s.take_output(), "TP\r\n-7200\r\n>");
  EXPECT_TRUE(s.paused());
  s.receive("TPSR\r");  // arrives while waiting: queued behind the store
  EXPECT_EQ(s.take_output(), "");
  s.peer_closed();
  EXPECT_FALSE(s.finished());
  ASSERT_TRUE(held);
  held(od::AbortCode::none);
  EXPECT_EQ(wakes, 1);
  EXPECT_FALSE(s.paused());
  EXPECT_EQ(s.take_output(),
            "OW1010,1,1702257011\r\nOW1010,1,1702257011,OK\r\n>TS\r\n1\r\n>TP\r\n-7200\r\n>TPSR\r\n0000010a\r\n>");
  EXPECT_TRUE(s.finished());
}

TEST_F(SessionTest, LateReplyAfterTheSessionIsGoneIsDropped) {
  od::Done held;
  d_.release_store_hooks();  // this test's hook stands in for the persistence service
  od_.on_write(0x1010, 1, [&](od::WriteRequest& r) {
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  {
    Session s(in_);
    s.receive("OW1010,1,1702257011\r");
    EXPECT_TRUE(s.paused());
  }
  ASSERT_TRUE(held);
  held(od::AbortCode::none);  // must not touch the destroyed session
  SUCCEED();
}

TEST_F(SessionTest, FinAnswersCompleteLinesAndDropsTheRest) {
  Session s(in_);
  s.receive("TP\rTS");
  EXPECT_FALSE(s.finished());
  s.peer_closed();
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.take_output(), "TP\r\n-7200\r\n>");
  s.receive("\r");  // nothing is read after FIN; the unterminated "TS" is gone
  EXPECT_EQ(s.take_output(), "");
}

TEST_F(SessionTest, GarbageNeverDesynchronises) {
  Session s(in_);
  std::uint32_t seed = 7;
  for (int i = 0; i < 2000; ++i) {
    std::string junk;
    for (int k = 0; k < 64; ++k) {
      seed = seed * 1103515245 + 12345;
      const char c = static_cast<char>(seed >> 16);
      if (c != '\r' && c != '\n') junk.push_back(c);
    }
    s.receive(junk);
    s.receive("\r");
    (void)s.take_output();
    s.receive("TP\r");
    ASSERT_EQ(s.take_output(), "TP\r\n-7200\r\n>") << i;
  }
}

// The taps of refgo.md §13: every complete line reaches the observer with its raw bytes; with a
// reply sink every reply unit (the ">" of an over-long line too) goes there, one call per reply,
// in order, and nothing is left in the output queue.
TEST_F(SessionTest, ObserverAndReplySinkSeeEveryLineAndReply) {
  Session s(in_);
  std::vector<line::Line> lines;
  std::vector<std::string> replies;
  Session::Observer o;
  o.received = [&](const line::Line& l) { lines.push_back(l); };
  s.set_observer(std::move(o));
  s.set_reply_sink([&](std::string r) { replies.push_back(std::move(r)); });
  s.receive("TP\r\nTS\n" + std::string(300, 'A') + "\r\r");
  EXPECT_EQ(s.take_output(), "");
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0].raw, "TP\r");
  EXPECT_EQ(lines[1].raw, "TS\n");
  EXPECT_TRUE(lines[2].overlong);
  EXPECT_EQ(lines[3].raw, "\r");
  ASSERT_EQ(replies.size(), 4u);
  EXPECT_EQ(replies[0], "TP\r\n-7200\r\n>");
  EXPECT_EQ(replies[1].substr(0, 4), "TS\r\n");
  EXPECT_EQ(replies[2], ">");
  EXPECT_EQ(replies[3], ">");
}

// Lines handed to an attached script are reported, and so are those dropped because 64 wait
// (refgo.md §5.4: "toScript", "discarded" in the trace).
TEST_F(SessionTest, ObserverSeesLinesForTheScriptAndTheDiscardedOnes) {
  Session s(in_);
  std::vector<std::pair<std::string, bool>> forwarded;
  Session::Observer o;
  o.to_script = [&](std::string_view text, bool discarded) { forwarded.emplace_back(std::string(text), discarded); };
  s.set_observer(std::move(o));
  in_.attachment().open(AttachMode::script_only);
  std::string input;
  for (std::size_t i = 0; i < k_max_script_lines + 1; ++i) {
    input += 'x';
    input += std::to_string(i);
    input += '\r';
  }
  s.receive(input);
  EXPECT_EQ(s.take_output(), "") << "mode 3: the script answers";
  ASSERT_EQ(forwarded.size(), k_max_script_lines + 1);
  EXPECT_EQ(forwarded[0], std::make_pair(std::string("x0"), false));
  EXPECT_FALSE(forwarded[k_max_script_lines - 1].second);
  EXPECT_TRUE(forwarded[k_max_script_lines].second) << "the 65th line is dropped";
  in_.attachment().close();
}

}  // namespace
}  // namespace mcemu::refgo
