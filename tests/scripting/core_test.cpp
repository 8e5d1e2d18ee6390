// Unit tests of the pure parts of the script engine (scripting/core): the IPC codec, the script
// source (tags, CRC-32, placeholder, record), the console output rules and the life-cycle table.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scripting/core/console_output.hpp"
#include "scripting/core/ipc.hpp"
#include "scripting/core/lifecycle.hpp"
#include "scripting/core/script_source.hpp"

namespace mcemu::scripting {
namespace {

using ipc::Value;

// ---- IPC codec

TEST(IpcCodec, FrameRoundTripAndLayout) {
  const std::string f = ipc::encode(ipc::Kind::output, "hi");
  EXPECT_EQ(f, std::string("\x03\x00\x00\x00Ohi", 7));
  const auto d = ipc::decode(f);
  ASSERT_TRUE(d.message);
  EXPECT_EQ(d.consumed, 7U);
  EXPECT_EQ(d.message->kind, ipc::Kind::output);
  EXPECT_EQ(d.message->body, "hi");
}

TEST(IpcCodec, EverySplitOfTwoFramesGivesTheSameMessages) {
  const std::string stream =
      ipc::encode(ipc::Kind::call, ipc::encode_call({7, {Value::integer(-5)}})) + ipc::encode(ipc::Kind::wake, "");
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    std::string buffer;
    std::vector<ipc::Message> got;
    for (const auto& part : {stream.substr(0, cut), stream.substr(cut)}) {
      buffer += part;
      for (;;) {
        const auto d = ipc::decode(buffer);
        ASSERT_FALSE(d.error);
        if (!d.message) break;
        got.push_back(*d.message);
        buffer.erase(0, d.consumed);
      }
    }
    ASSERT_EQ(got.size(), 2U) << cut;
    EXPECT_EQ(got[1].kind, ipc::Kind::wake);
    const auto call = ipc::decode_call(got[0].body);
    ASSERT_TRUE(call);
    EXPECT_EQ(call->function, 7);
    EXPECT_EQ(call->args, (std::vector<Value>{Value::integer(-5)}));
  }
}

TEST(IpcCodec, BadLengthsAndKindsAreErrors) {
  EXPECT_TRUE(ipc::decode(std::string("\x00\x00\x00\x00", 4)).error);
  EXPECT_TRUE(ipc::decode(std::string("\x00\x00\x20\x00O", 5)).error);  // 2 MiB
  EXPECT_TRUE(ipc::decode(std::string("\x01\x00\x00\x00?", 5)).error);
  EXPECT_FALSE(ipc::decode(std::string("\x05\x00\x00", 3)).message);  // need more
}

TEST(IpcCodec, ValuesRoundTripAndRejectTruncation) {
  const std::vector<Value> v{Value::none(), Value::integer(-2147483648LL), Value::bytes(std::string("\0\xff", 2)),
                             Value::text("tëxt")};
  const std::string body = ipc::encode_values(v);
  EXPECT_EQ(ipc::decode_values(body), v);
  for (std::size_t n = 0; n < body.size(); ++n) EXPECT_FALSE(ipc::decode_values(body.substr(0, n))) << n;
  EXPECT_FALSE(ipc::decode_values(body + "x"));
  EXPECT_FALSE(ipc::decode_values(std::string("\x01\x00Q", 3)));
}

TEST(IpcCodec, ValueCountsUpToTheBytesLeftDecode) {
  // 65 535 `none` values take one byte each: the largest count fits exactly, one byte short is refused.
  const std::vector<Value> nones(65535, Value::none());
  const std::string body = ipc::encode_values(nones);
  ASSERT_EQ(body.size(), 2u + 65535u);
  EXPECT_EQ(ipc::decode_values(body), nones);
  EXPECT_FALSE(ipc::decode_values(std::string_view(body).substr(0, body.size() - 1)));
  EXPECT_FALSE(ipc::decode_values(std::string("\xff\xff", 2)));
}

TEST(IpcCodec, NetRequestsRoundTripAndBadOnesAreRefused) {
  using K = ipc::NetRequest::Kind;
  for (const ipc::NetRequest& r : {ipc::NetRequest{K::server, "", 5000}, ipc::NetRequest{K::client, "plc.local", 502},
                                   ipc::NetRequest{K::udp, "10.0.0.1", 65535}, ipc::NetRequest{K::udp, "", 1}}) {
    EXPECT_EQ(ipc::decode_net(ipc::encode_net(r)), r);
  }
  const auto values = [](std::vector<Value> v) { return ipc::encode_values(v); };
  EXPECT_FALSE(ipc::decode_net(values({Value::text("raw"), Value::text(""), Value::integer(1)})));
  EXPECT_FALSE(ipc::decode_net(values({Value::text("server"), Value::text(""), Value::integer(0)})));
  EXPECT_FALSE(ipc::decode_net(values({Value::text("server"), Value::text(""), Value::integer(65536)})));
  EXPECT_FALSE(ipc::decode_net(values({Value::text("client"), Value::text(""), Value::integer(80)}))) << "no host";
  EXPECT_FALSE(ipc::decode_net(values({Value::text("server"), Value::none(), Value::integer(80)})));
  EXPECT_FALSE(ipc::decode_net(values({Value::text("server"), Value::text("")})));
  const std::string ok = ipc::encode_net({K::client, "h", 1});
  for (std::size_t n = 0; n < ok.size(); ++n) EXPECT_FALSE(ipc::decode_net(ok.substr(0, n))) << n;
  EXPECT_FALSE(ipc::decode(std::string("\x01\x00\x00\x00N", 5)).error) << "'N' is a known kind";
}

// ---- script source (scripting.md §2)

TEST(ScriptSource, PlaceholderMatchesTheRealDrive) {
  const ScriptSource p;
  EXPECT_EQ(p.id(), "(empty)");
  EXPECT_EQ(p.length(), 13U);
  EXPECT_EQ(p.crc32(), 0x23883CEFU);
  EXPECT_TRUE(p.is_placeholder());
  EXPECT_TRUE(p.record().is_null());
}

TEST(ScriptSource, IdTag) {
  EXPECT_EQ(script_id("#id maxTRACK N23 demo rev8\r\nimport drive\n"), "maxTRACK N23 demo rev8");
  EXPECT_EQ(script_id("# a\n# b\n\n\n\n#id\tline six  \r\n"), "line six");
  EXPECT_EQ(script_id("import sys\n"), "(empty)");
  EXPECT_EQ(script_id(" #id not column one\n#idx no\n#id   \n"), "(empty)");
  EXPECT_EQ(script_id("#id first\n#id second\n"), "first");
  EXPECT_EQ(script_id("#id " + std::string(80, 'a')), std::string(64, 'a'));
  // cut at a character boundary: 63 ASCII + a 2-byte character would need 65 bytes
  EXPECT_EQ(script_id("#id " + std::string(63, 'a') + "\xc3\xa4"), std::string(63, 'a'));
}

TEST(ScriptSource, PrivateTagHidesTheRest) {
  const auto s = ScriptSource::from_bytes("#id x\nprint(1)\n#private\nsecret()\n");
  EXPECT_TRUE(s.has_private());
  EXPECT_EQ(s.visible(), "#id x\nprint(1)\n");
  const auto t = ScriptSource::from_bytes("print(1)\n  #private\n");
  EXPECT_FALSE(t.has_private());
  EXPECT_EQ(t.visible(), t.bytes());
}

TEST(ScriptSource, RecordRoundTripUtf8AndBinary) {
  const auto a = ScriptSource::from_bytes("#id ä\nprint(1)\n");
  const auto ra = a.record();
  EXPECT_EQ(ra["encoding"], "utf-8");
  EXPECT_EQ(ra["id"], "ä");
  EXPECT_EQ(ScriptSource::from_record(ra).bytes(), a.bytes());
  const auto b = ScriptSource::from_bytes("#id w\n# \xe4 Latin-1 umlaut\n");
  const auto rb = b.record();
  EXPECT_EQ(rb["encoding"], "base64");
  EXPECT_EQ(ScriptSource::from_record(rb).bytes(), b.bytes());
  EXPECT_EQ(ScriptSource::from_record(rb).crc32(), b.crc32());
  EXPECT_TRUE(ScriptSource::from_record(nullptr).is_placeholder());
  EXPECT_TRUE(ScriptSource::from_record({{"source", 5}}).is_placeholder());
  EXPECT_TRUE(ScriptSource::from_record({{"source", "!!"}, {"encoding", "base64"}}).is_placeholder());
}

TEST(ScriptSource, Base64) {
  for (const std::string& s : std::vector<std::string>{"", "f", "fo", "foo", "foob", std::string("\0\xff\x10", 3)}) {
    bool ok = false;
    EXPECT_EQ(base64_decode(base64_encode(s), ok), s);
    EXPECT_TRUE(ok);
  }
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
}

TEST(ScriptSource, Utf8Validation) {
  EXPECT_TRUE(is_valid_utf8("abc \xc3\xa4 \xe2\x82\xac \xf0\x9f\x98\x80"));
  EXPECT_FALSE(is_valid_utf8("\xe4"));
  EXPECT_FALSE(is_valid_utf8("\xc0\xaf"));      // overlong
  EXPECT_FALSE(is_valid_utf8("\xed\xa0\x80"));  // surrogate
  EXPECT_FALSE(is_valid_utf8("\xe2\x82"));      // truncated
}

// ---- console output (udp-debug.md §4.3–§4.6)

TEST(ConsoleOutput, EveryLfBecomesCrlfAndEndsAMessage) {
  OutputCooker c;
  EXPECT_EQ(c.write("a\nb\r\nc", 0), (std::vector<std::string>{"a\r\n", "b\r\r\n"}));
  EXPECT_TRUE(c.holding());
}

TEST(ConsoleOutput, PartialLineAfter50ms) {
  OutputCooker c;
  c.write("x", 10);
  c.write("y", 40);  // later output does not extend the 50 ms
  EXPECT_EQ(c.deadline_ms(), 60U);
  EXPECT_FALSE(c.on_step(59));
  EXPECT_EQ(c.on_step(60), "xy");
  EXPECT_FALSE(c.deadline_ms());
}

TEST(ConsoleOutput, CodeLines) {
  EXPECT_EQ(starting_line("maxTRACK N23 demo rev8"), "code: starting, script id: maxTRACK N23 demo rev8\n\r");
  EXPECT_EQ(compile_line("i"), "code: compile, script id: i\n\r");
  EXPECT_EQ(execute_line("i"), "code: execute, script id: i\n\r");
  EXPECT_EQ(unavailable_line("i"), "code: engine unavailable, script id: i\n\r");
  EXPECT_EQ(failure_signal_line(11, "i"), "code: engine failure (signal 11), script id: i\n\r");
  EXPECT_EQ(failure_exit_line(3, "i"), "code: engine failure (exit status 3), script id: i\n\r");
  EXPECT_EQ(engine_note_line("no sandbox"), "code: no sandbox\n\r");
}

// ---- life cycle (scripting.md §3.2): every row, in every state

struct Row {
  Trigger trigger;
  RunState from;
  RunState next;
  bool terminate;
  SourceChange source;
  bool launch;
  bool freeze;
  bool thaw;
};

constexpr RunState OFF = RunState::off, RUN = RunState::run, BRK = RunState::brk;
constexpr auto NONE = SourceChange::none;

const Row k_rows[] = {
    {Trigger::start, OFF, RUN, false, NONE, true, false, false},
    {Trigger::start, RUN, RUN, false, NONE, false, false, false},
    {Trigger::start, BRK, BRK, false, NONE, false, false, false},
    {Trigger::restart, OFF, RUN, false, NONE, true, false, false},
    {Trigger::restart, RUN, RUN, true, NONE, true, false, false},
    {Trigger::restart, BRK, RUN, true, NONE, true, false, false},
    {Trigger::stop, OFF, OFF, false, NONE, false, false, false},
    {Trigger::stop, RUN, OFF, true, NONE, false, false, false},
    {Trigger::stop, BRK, OFF, true, NONE, false, false, false},
    {Trigger::pause, OFF, OFF, false, NONE, false, false, false},
    {Trigger::pause, RUN, BRK, false, NONE, false, true, false},
    {Trigger::pause, BRK, BRK, false, NONE, false, false, false},
    {Trigger::resume, OFF, OFF, false, NONE, false, false, false},
    {Trigger::resume, RUN, RUN, false, NONE, false, false, false},
    {Trigger::resume, BRK, RUN, false, NONE, false, false, true},
    {Trigger::finished, RUN, OFF, true, NONE, false, false, false},
    {Trigger::engine_died, RUN, OFF, true, NONE, false, false, false},
    {Trigger::engine_died, BRK, OFF, true, NONE, false, false, false},
    {Trigger::upload, OFF, OFF, false, SourceChange::uploaded, false, false, false},
    {Trigger::upload, RUN, OFF, true, SourceChange::uploaded, false, false, false},
    {Trigger::upload, BRK, OFF, true, SourceChange::uploaded, false, false, false},
    {Trigger::delete_script, OFF, OFF, false, SourceChange::placeholder, false, false, false},
    {Trigger::delete_script, RUN, OFF, true, SourceChange::placeholder, false, false, false},
    {Trigger::factory_reset, BRK, OFF, true, SourceChange::placeholder, false, false, false},
    {Trigger::factory_reset, OFF, OFF, false, SourceChange::placeholder, false, false, false},
    {Trigger::power_cycle, RUN, OFF, true, SourceChange::stored, false, false, false},
    {Trigger::power_cycle, OFF, OFF, false, SourceChange::stored, false, false, false},
    {Trigger::reset_node, BRK, OFF, true, SourceChange::stored, false, false, false},
};

class LifecycleTable : public ::testing::TestWithParam<Row> {};

TEST_P(LifecycleTable, Row) {
  const Row& r = GetParam();
  const Decision d = decide(r.from, r.trigger);
  EXPECT_EQ(d.next, r.next);
  EXPECT_EQ(d.terminate, r.terminate);
  EXPECT_EQ(d.source, r.source);
  EXPECT_EQ(d.launch, r.launch);
  EXPECT_EQ(d.freeze, r.freeze);
  EXPECT_EQ(d.thaw, r.thaw);
}
INSTANTIATE_TEST_SUITE_P(Scripting, LifecycleTable, ::testing::ValuesIn(k_rows));

TEST(Lifecycle, ControlObjectsAndCodeAct) {
  EXPECT_EQ(run_control_trigger(0, RUN), Trigger::stop);
  EXPECT_EQ(run_control_trigger(1, OFF), Trigger::start);
  EXPECT_EQ(run_control_trigger(1, BRK), Trigger::resume);
  EXPECT_EQ(run_control_trigger(1, RUN), Trigger::start);  // start does nothing while RUN
  EXPECT_EQ(run_control_trigger(2, RUN), Trigger::pause);
  EXPECT_FALSE(run_control_trigger(3, RUN));
  EXPECT_EQ(program_control_trigger(0), Trigger::stop);
  EXPECT_EQ(program_control_trigger(1), Trigger::start);
  EXPECT_EQ(program_control_trigger(2), Trigger::restart);
  EXPECT_EQ(program_control_trigger(3), Trigger::delete_script);
  EXPECT_EQ(code_act_trigger(1), Trigger::pause);
  EXPECT_EQ(code_act_trigger(2), Trigger::resume);
  EXPECT_EQ(code_act_trigger(3), Trigger::restart);
  EXPECT_EQ(code_act_trigger(4), Trigger::stop);
  EXPECT_FALSE(code_act_trigger(5));
  EXPECT_FALSE(code_act_trigger(0));
  EXPECT_EQ(run_control_value(BRK), 2);
  EXPECT_EQ(to_string(BRK), "BRK");
}

}  // namespace
}  // namespace mcemu::scripting
