// Scripted conversations of slcan-canopen.md §3.8 against the session, with a scripted node
// standing in for the CANopen node (the same examples run against the real node in
// tests/server/canopen_bus_test.cpp). Every input is also fed split at every byte offset and byte
// by byte (§3.2 rule 7).
#include "protocols/slcan/session.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>

namespace mcemu::slcan {
namespace {

using namespace std::chrono_literals;

can::Frame frame(std::string_view line) {
  auto r = parse_line(line);
  return std::get<Command>(r).frame;
}

// A scripted node: answers known request frames with fixed frames, delivered to every session.
struct ScriptedBus {
  std::map<std::string, std::vector<std::string>> script;
  std::vector<std::unique_ptr<Session>> sessions;
  std::vector<can::Frame> received;

  Session& add(SlcanConfig cfg = {}) {
    sessions.push_back(std::make_unique<Session>(
        cfg, [this](const can::Frame& f) { on_client_frame(f); }, [] { return 0x44444444u; }));
    return *sessions.back();
  }
  void on_client_frame(const can::Frame& f) {
    received.push_back(f);
    for (auto& [k, replies] : script) {
      if (frame(k) != f) continue;
      for (const auto& r : replies) {
        for (auto& s : sessions) s->deliver(frame(r), 0ms);
      }
    }
  }
};

const std::map<std::string, std::vector<std::string>> k_node = {
    {"t63284041600000000000", {"t5B284B41600040000000"}},
    {"t6328407a600000000000", {"t5B28437A600000000000"}},
    {"t00020132", {"t1B224000", "t2B23400000"}},
    {"r7321", {"t73217F"}},
};

struct Conversation {
  const char* name;
  std::string input;
  std::string output;
  FrameAck ack = FrameAck::z;
};

class Example : public ::testing::TestWithParam<Conversation> {};

std::string run(const Conversation& c, const std::vector<std::string_view>& chunks) {
  ScriptedBus bus;
  bus.script = k_node;
  SlcanConfig cfg;
  cfg.frame_ack = c.ack;
  Session& s = bus.add(cfg);
  std::string out;
  for (auto chunk : chunks) {
    s.receive(chunk);
    out += s.take_output();
  }
  return out;
}

TEST_P(Example, ByteExactForEverySplit) {
  const auto& c = GetParam();
  EXPECT_EQ(run(c, {c.input}), c.output);
  for (std::size_t cut = 0; cut <= c.input.size(); ++cut) {
    const std::string_view in = c.input;
    EXPECT_EQ(run(c, {in.substr(0, cut), in.substr(cut)}), c.output) << "cut at " << cut;
  }
  std::vector<std::string_view> bytes;
  for (std::size_t i = 0; i < c.input.size(); ++i) bytes.push_back(std::string_view(c.input).substr(i, 1));
  EXPECT_EQ(run(c, bytes), c.output) << "byte by byte";
}

// §3.8 rows 2–32, 34, 35 (row 1 "nothing on connect", 15 and 33 below).
INSTANTIATE_TEST_SUITE_P(
    Spec, Example,
    ::testing::Values(
        Conversation{"r02_python_can_open", "O\r", "\r"},
        Conversation{"r03_python_can_41_bitrate", "C\rS4\rO\rO\r", "\r\r\r\r"},
        Conversation{"r04_python_can_46_bitrate", "C\rS4\r\rO\rO\r", "\r\r\r\r\r"},
        Conversation{"r05_listen_only", "L\r", "\r"}, Conversation{"r06_shutdown", "C\r", "\r"},
        Conversation{"r07_slcand", "C\rS5\rF\rO\r", "\r\rF00\r\r"}, Conversation{"r08_version", "V\r", "V1010\r"},
        Conversation{"r09_serial", "N\r", "N4444\r"},
        Conversation{"r10_sdo_read", "t63284041600000000000\r", "z\rt5B284B41600040000000\r"},
        Conversation{"r11_lower_case", "t6328407a600000000000\r", "z\rt5B28437A600000000000\r"},
        Conversation{"r12_nmt_start", "t00020132\r", "z\rt1B224000\rt2B23400000\r"},
        Conversation{"r13_29_bit", "T12ABCDEF2AA55\r", "Z\r"},
        Conversation{"r14_guarding_rtr", "r7321\r", "z\rt73217F\r"}, Conversation{"r16_flags", "F\r", "F00\r"},
        Conversation{"r17_empty_line", "\r", "\r"}, Conversation{"r18_crlf", "O\r\n", "\r"},
        Conversation{"r19_bad_hex", "t63G0\r", "\a"}, Conversation{"r20_dlc9", "t63290000000000000000\r", "\a"},
        Conversation{"r21_too_few_digits", "t6328404160\r", "\a"},
        Conversation{"r22_too_many_digits", "t080000\r", "\a"}, Conversation{"r23_id_above_7ff", "t8000\r", "\a"},
        Conversation{"r24_id_above_1fffffff", "T200000000\r", "\a"},
        Conversation{"r25_rtr_with_data", "r732100\r", "\a"}, Conversation{"r26_unknown", "K\r", "\a"},
        Conversation{"r27_extra_chars", "O1\r", "\a"},
        Conversation{"r28_closed_then_reopen", "C\rt0800\rO\r", "\r\a\r"},
        Conversation{"r29_listen_sends_frame", "L\rt0800\r", "\r\a"},
        Conversation{"r30_overlong", std::string(100, 'A') + "\r", "\a"},
        Conversation{"r31_ack_cr", "t0800\r", "\r", FrameAck::cr}, Conversation{"r32_space", "t 0800\r", "\a"},
        Conversation{"r34_lf_line_ends", "V\nF\n", "V1010\rF00\r"}, Conversation{"r35_lf_then_cr", "O\n\r", "\r\r"},
        // beyond the table
        Conversation{"ack_none", "t0800\rT000000010\r", "", FrameAck::none}, Conversation{"lower_v", "v\r", "v1010\r"},
        Conversation{"remembered_settings", "s031C\rM00000000\rmFFFFFFFF\rW2\rX1\rQ0\rU6\rZ0\rZ1\r",
                     "\r\r\r\r\r\r\r\r\r"},
        Conversation{"redundant_open_close", "O\rO\rC\rC\rL\rO\r", "\r\r\r\r\r\r"},
        Conversation{"frame_while_listen_then_open", "L\rt0800\rO\rt0800\r", "\r\a\rz\r"},
        Conversation{"control_byte", "V\x01\r", "\a"}, Conversation{"bel_in_line", "\aV\r", "\a"},
        Conversation{"nul_in_line", std::string("V\0\r", 3), "\a"}, Conversation{"high_byte", "V\xC3\xA4\r", "\a"},
        Conversation{"exactly_64", "t" + std::string(63, '0') + "\r", "\a"},
        Conversation{"overlong_then_ok", std::string(65, 'V') + "\rV\r", "\aV1010\r"},
        Conversation{"unterminated_gets_nothing", "V\rV", "V1010\r"},
        Conversation{"malformed_then_continues", "t63G0\rXYZ\r\x7F\rt0800\rV\r", "\a\a\az\rV1010\r"}),
    [](const ::testing::TestParamInfo<Conversation>& i) { return std::string(i.param.name); });

TEST(Session, NothingOnConnect) {  // §3.8 row 1
  ScriptedBus bus;
  Session& s = bus.add();
  EXPECT_EQ(s.take_output(), "");
  EXPECT_EQ(s.state(), ChannelState::open);
  EXPECT_FALSE(s.finished());
}

TEST(Session, TimestampsAfterZ1) {  // §3.8 row 15
  ScriptedBus bus;
  Session& s = bus.add();
  s.deliver(frame("t73217F"), 6703ms);
  s.receive("Z1\r");
  s.deliver(frame("t73217F"), 6703ms);
  s.receive("Z0\r");
  s.deliver(frame("t73217F"), 6703ms);
  EXPECT_EQ(s.take_output(), "t73217F\r\rt73217F1A2F\r\rt73217F\r");
}

TEST(Session, TwoClientsSeeNodeFramesButNotEachOther) {  // §3.8 row 33, §3.7
  ScriptedBus bus;
  bus.script = k_node;
  Session& a = bus.add();
  Session& b = bus.add();
  a.receive("t63284041600000000000\r");
  EXPECT_EQ(a.take_output(), "z\rt5B284B41600040000000\r");
  EXPECT_EQ(b.take_output(), "t5B284B41600040000000\r");
  b.receive("t0800\r");  // a frame nobody answers: acknowledged to B, invisible to A
  EXPECT_EQ(b.take_output(), "z\r");
  EXPECT_EQ(a.take_output(), "");
  ASSERT_EQ(bus.received.size(), 2u);
}

TEST(Session, ClosedSessionDropsNodeFramesListenKeepsThem) {
  ScriptedBus bus;
  Session& s = bus.add();
  s.receive("C\r");
  s.deliver(frame("t73217F"), 0ms);
  EXPECT_EQ(s.take_output(), "\r");
  s.receive("L\r");
  s.deliver(frame("t73217F"), 0ms);
  EXPECT_EQ(s.take_output(), "\rt73217F\r");
  EXPECT_EQ(s.state(), ChannelState::listen);
}

TEST(Session, FramesReachTheNodeOnlyWhenValidAndOpen) {
  ScriptedBus bus;
  Session& s = bus.add();
  s.receive("t63G0\rC\rt0800\rO\rt0801AA\rT12ABCDEF2AA55\rr7321\r");
  ASSERT_EQ(bus.received.size(), 3u);
  EXPECT_EQ(bus.received[0], (can::Frame{0x080, false, false, 1, {0xAA}}));
  EXPECT_EQ(bus.received[1], (can::Frame{0x12ABCDEF, true, false, 2, {0xAA, 0x55}}));
  EXPECT_EQ(bus.received[2], (can::Frame{0x732, false, true, 1, {}}));
}

TEST(Session, SerialWithEightDigits) {
  ScriptedBus bus;
  SlcanConfig cfg;
  cfg.serial_digits = 8;
  cfg.version = "0042";
  Session& s = bus.add(cfg);
  s.receive("N\rV\r");
  EXPECT_EQ(s.take_output(), "N44444444\rV0042\r");
}

TEST(Session, PeerClosedFinishesAfterAnsweringCompleteLines) {
  ScriptedBus bus;
  Session& s = bus.add();
  s.receive("V\rF");
  s.peer_closed();
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.take_output(), "V1010\r");
  s.deliver(frame("t73217F"), 0ms);
  EXPECT_EQ(s.take_output(), "");
}

TEST(Session, NodeFramesWakeTheAdapter) {
  ScriptedBus bus;
  Session& s = bus.add();
  int wakes = 0;
  s.set_wake([&] { ++wakes; });
  s.deliver(frame("t73217F"), 0ms);
  s.deliver(frame("t73217F"), 0ms);
  EXPECT_EQ(wakes, 2);
  s.receive("V\r");  // replies are collected after receive(): no wake needed
  EXPECT_EQ(wakes, 2);
  EXPECT_EQ(s.take_output(), "t73217F\rt73217F\rV1010\r");
}

TEST(Session, TraceReportsLinesRepliesAndReasons) {
  ScriptedBus bus;
  Session& s = bus.add();
  std::vector<TraceEvent> trace;
  s.set_trace([&](const TraceEvent& e) { trace.push_back(e); });
  s.receive("t63G0\rL\r" + std::string(70, 'x') + "\r");
  ASSERT_EQ(trace.size(), 9u);
  EXPECT_EQ(trace[0].dir, TraceEvent::Dir::rx);
  EXPECT_EQ(trace[0].text, "t63G0\r") << "raw, with its line end (slcan-canopen.md §11.2)";
  EXPECT_EQ(trace[1].dir, TraceEvent::Dir::event);
  EXPECT_EQ(trace[1].text, "BEL: not a hex digit");
  EXPECT_EQ(trace[2].text, "\a");
  EXPECT_EQ(trace[4].text, "state LISTEN");
  EXPECT_TRUE(trace[6].overlong);
  EXPECT_EQ(trace[6].text.size(), 64u);
}

// slcan.bel (slcan-canopen.md §11.3): the lines asked while the fault says so are answered BEL
// and have no other effect (a frame is not handed to the node); over-long lines do not ask.
TEST(Session, BelFaultAnswersTheNextLinesWithBel) {
  ScriptedBus bus;
  bus.script = k_node;
  Session& s = bus.add();
  int left = 2;
  int asked = 0;
  s.set_bel_fault([&] {
    ++asked;
    if (left == 0) return false;
    --left;
    return true;
  });
  std::vector<TraceEvent> trace;
  s.set_trace([&](const TraceEvent& e) { trace.push_back(e); });
  s.receive(std::string(70, 'x') + "\r");
  EXPECT_EQ(s.take_output(), "\a");
  EXPECT_EQ(asked, 0) << "an over-long line is BEL anyway";
  s.receive("V\rt63284041600000000000\rV\r");
  EXPECT_EQ(s.take_output(), "\a\aV1010\r");
  EXPECT_TRUE(bus.received.empty()) << "the frame answered BEL never reached the node";
  EXPECT_TRUE(std::any_of(trace.begin(), trace.end(),
                          [](const TraceEvent& e) { return e.text == "BEL: injected (slcan.bel)"; }));
  s.receive("t63284041600000000000\r");
  EXPECT_EQ(s.take_output(), "z\rt5B284B41600040000000\r");
}

// slcan.rawTx: the text goes out as it is, in every session state, and is traced as output.
TEST(Session, SendRawInAnyState) {
  ScriptedBus bus;
  Session& s = bus.add();
  int wakes = 0;
  s.set_wake([&] { ++wakes; });
  s.receive("C\r");
  EXPECT_EQ(s.take_output(), "\r");
  std::vector<TraceEvent> trace;
  s.set_trace([&](const TraceEvent& e) { trace.push_back(e); });
  s.send_raw("t12\r");
  EXPECT_EQ(s.take_output(), "t12\r");
  EXPECT_EQ(wakes, 1);
  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace[0].dir, TraceEvent::Dir::tx);
  EXPECT_EQ(trace[0].text, "t12\r");
}

}  // namespace
}  // namespace mcemu::slcan
