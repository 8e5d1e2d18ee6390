// The module-function table of the script engine (scripting/core/calls.hpp) against a real
// dictionary, core and RefGo interpreter: every mcdrive function's object writes and returns
// (scripting.md §5.5), refgo.cmd's return types (§6.2), the attachment calls (§6.3–§6.6) and the
// rejection of malformed calls. The engine tests repeat the important ones through python3.
#include "scripting/core/calls.hpp"

#include <gtest/gtest.h>

#include <set>

#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/session.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::scripting {
namespace {

using ipc::Value;

class CallsTest : public ::testing::Test {
 protected:
  // Calls a function by name with integer or text arguments; returns the single reply value.
  Value call(std::string_view name, std::vector<Value> args = {}) {
    const FunctionRow* row = nullptr;
    for (const auto& r : function_table()) {
      if (r.name == name) row = &r;
    }
    EXPECT_NE(row, nullptr) << name;
    bool malformed = false;
    auto r = execute_call(
        ctx_, {row->id, std::move(args)}, [this](Values v) { late_ = v; }, malformed);
    EXPECT_FALSE(malformed) << name;
    d_.core.drain_events();
    if (!r) return Value::text("<pending>");
    EXPECT_EQ(r->size(), 1U);
    return r->at(0);
  }
  static Value i(std::int64_t v) { return Value::integer(v); }
  static Value t(std::string s) { return Value::text(std::move(s)); }
  std::uint16_t state_bits() const { return static_cast<std::uint16_t>(d_.get(0x6041) & 0x6F); }

  refgo::test::Drive d_;
  CallContext ctx_{{d_.core, d_.od, od::Origin::script}, d_.in, [this](std::string s) { refusals_.push_back(s); }};
  std::vector<std::string> refusals_;
  std::optional<Values> late_;
};

TEST_F(CallsTest, IdsAreUniqueAndStable) {
  std::set<std::uint16_t> ids;
  for (const auto& r : function_table()) EXPECT_TRUE(ids.insert(r.id).second) << r.name;
  EXPECT_EQ(find_function(1)->name, "WriteObject");
  EXPECT_EQ(find_function(40)->name, "cmd");
  EXPECT_EQ(table_values().size(), function_table().size() * 5);
}

TEST_F(CallsTest, WriteAndReadObject) {
  EXPECT_EQ(call("WriteObject", {i(0x6083), i(0), i(1234)}), i(0));
  EXPECT_EQ(call("ReadObject", {i(0x6083), i(0)}), i(1234));
  EXPECT_EQ(call("WriteObject", {i(0x6041), i(0), i(5)}), i(0x06010002));
  EXPECT_EQ(call("WriteObject", {i(0x1234), i(0), i(5)}), i(0x06020000));
  EXPECT_EQ(call("ReadObject", {i(0x1234), i(0)}), i(0x06020000));
  EXPECT_EQ(call("ReadObject", {i(0x1008), i(0)}), i(0x06070010));  // a string entry
  EXPECT_EQ(call("ReadObject", {i(0x10000), i(0)}), i(0x06020000));
  // a U32 ≥ 2^31 reads back negative; a negative value writes its two's complement
  EXPECT_EQ(call("WriteObject", {i(0x6081), i(0), i(-2)}), i(0));
  EXPECT_EQ(d_.get(0x6081), 4294967294LL);
  EXPECT_EQ(call("ReadObject", {i(0x6081), i(0)}), i(-2));
}

TEST_F(CallsTest, GoPosAbsFromSodAutoenables) {
  ASSERT_EQ(state_bits(), 0x40);  // switch on disabled
  EXPECT_EQ(call("GoPosAbs", {i(1000)}), Value::none());
  EXPECT_EQ(state_bits(), 0x27);
  EXPECT_EQ(d_.get(0x6060), 1);
  EXPECT_EQ(d_.get(0x607A), 1000);
  EXPECT_EQ(call("ChkMoving"), i(1));  // visible at once (scripting.md §5.6)
  EXPECT_EQ(call("ChkReady"), i(0));
  d_.step_until([&] { return d_.reached(); }, 20000);
  EXPECT_EQ(call("ChkReady"), i(1));
  EXPECT_EQ(call("GetActualPos"), i(1000));
}

TEST_F(CallsTest, PowerQuitEnableDriveAndChecks) {
  EXPECT_EQ(call("EnableDrive"), i(1));
  EXPECT_EQ(call("ChkEnabled"), i(1));
  EXPECT_EQ(call("PowerQuit"), Value::none());
  EXPECT_EQ(state_bits(), 0x40);
  EXPECT_EQ(d_.get(0x6060), 0);
  EXPECT_EQ(call("ChkEnabled"), i(0));
  EXPECT_EQ(call("ChkError"), i(0));
  EXPECT_EQ(call("ReadStatusword"), i(d_.get(0x6041)));
}

TEST_F(CallsTest, StopAndContinueMotion) {
  call("GoPosAbs", {i(100000)});
  d_.step(50);
  call("StopMotion");
  EXPECT_EQ(d_.get(0x605A), 6);
  EXPECT_EQ(state_bits() & 0x6F, 0x07);  // quick stop active
  call("ContinueMotion");
  EXPECT_EQ(state_bits(), 0x27);
}

TEST_F(CallsTest, GoVelAndSetters) {
  call("SetAcc", {i(3000)});
  call("SetDec", {i(2000)});
  call("SetPosVel", {i(500)});
  call("SetTargetPos", {i(-5)});
  call("SetTorque", {i(800)});
  EXPECT_EQ(d_.get(0x6083), 3000);
  EXPECT_EQ(d_.get(0x6084), 2000);
  EXPECT_EQ(d_.get(0x6081), 500);
  EXPECT_EQ(d_.get(0x607A), -5);
  EXPECT_EQ(d_.get(0x6073), 800);
  call("GoVel", {i(720)});
  EXPECT_EQ(d_.get(0x6060), 3);
  EXPECT_EQ(d_.get(0x60FF), 720);
  EXPECT_EQ(call("GetOpMode"), i(3));
  EXPECT_TRUE(refusals_.empty());
  call("SetOpMode", {i(99)});  // refused by the OD: skipped and traced
  EXPECT_EQ(d_.get(0x6060), 3);
  ASSERT_EQ(refusals_.size(), 1U);
  EXPECT_EQ(refusals_[0], "SetOpMode: 6060h.00 := 99 refused, 06090030h");
}

TEST_F(CallsTest, GoHomeMethod35OutsideOeSetsHome) {
  call("GoHome", {i(35), i(0), i(0), i(0)});  // 609Ah := 0 is refused and skipped (§5.3)
  EXPECT_EQ(d_.get(0x6098), 35);
  EXPECT_EQ(d_.get(0x6060), 6);
  ASSERT_EQ(refusals_.size(), 1U);
  EXPECT_EQ(refusals_[0], "GoHome: 609Ah.00 := 0 refused, 06090032h");
  call("GoHome", {i(300), i(0), i(0), i(0)});  // not an i8: refused, nothing else
  EXPECT_EQ(refusals_.size(), 2U);
}

TEST_F(CallsTest, InputsAndOutputs) {
  EXPECT_EQ(call("ChkIn", {i(1)}), i(0));
  d_.set(0x3510, 1, 0x10000);  // simulate IN1 (iofunc.md 3510h.01)
  d_.core.recompute_inputs();
  EXPECT_EQ(call("ChkIn", {i(11)}), i(0));
  call("SetOut", {i(1)});
  call("SetOut", {i(4)});
  call("SetOut", {i(5)});  // no OUT5: nothing
  EXPECT_EQ(d_.get(0x60FE, 1), (1 << 16) | (1 << 19));
  call("ClearOut", {i(1)});
  EXPECT_EQ(d_.get(0x60FE, 1), 1 << 19);
  EXPECT_EQ(call("ChkMfrStatus", {i(40)}), i(0));
}

TEST_F(CallsTest, SendEmcyMsgQueuesAnEmcyWithDefaults) {
  call("SendEmcyMsg", {i(0x12345678)});
  SUCCEED();  // the frame itself is the core's (drive-core.md §11.8); here: no state change
  EXPECT_EQ(state_bits(), 0x40);
}

TEST_F(CallsTest, RefgoCmdReturnTypes) {
  EXPECT_EQ(call("cmd", {t("TS")}), i(0));
  EXPECT_EQ(call("cmd", {t("tp\r\n")}), i(0));
  EXPECT_EQ(call("cmd", {t("TPSR")}), i(std::stoll(d_.tpsr(), nullptr, 16)));
  EXPECT_EQ(call("cmd", {t("OR6041,0,h")}).tag, Value::Tag::text);
  EXPECT_EQ(call("cmd", {t("OW6091,1,1")}), t("OW6091,1,1,OK"));
  EXPECT_EQ(call("cmd", {t("TI3")}), t("0"));
  EXPECT_EQ(call("cmd", {t("SP720")}), t(""));
  EXPECT_EQ(call("cmd", {t("XYZ")}), Value::none());
  EXPECT_EQ(call("cmd", {t("")}), Value::none());
  EXPECT_EQ(call("cmd", {t("SO7")}), Value::none());
  EXPECT_EQ(call("cmd", {t("TP5")}), Value::none());
}

TEST_F(CallsTest, RefgoCmdBypassesTheAttachment) {
  d_.in.attachment().open(refgo::AttachMode::script_only);
  EXPECT_EQ(call("cmd", {t("TS")}), i(0));
}

TEST_F(CallsTest, RefgoAttachment) {
  refgo::Session s(d_.in);
  EXPECT_EQ(call("open", {i(4)}), i(-1));
  EXPECT_EQ(call("write", {Value::bytes("x")}), i(-1));  // not attached
  EXPECT_EQ(call("open", {i(2)}), i(0));
  s.receive("TT\r");
  EXPECT_EQ(call("read"), Value::bytes("TT"));
  EXPECT_EQ(call("read"), Value::none());
  EXPECT_EQ(call("write", {t("TT\r\n125\r\n>")}), i(0));
  EXPECT_EQ(s.take_output(), "TT\r\n125\r\n>");
  EXPECT_EQ(call("close"), Value::none());
  EXPECT_FALSE(d_.in.attachment().attached());
}

TEST_F(CallsTest, MalformedCallsAreRejected) {
  bool malformed = false;
  EXPECT_FALSE(execute_call(ctx_, {999, {}}, {}, malformed));
  EXPECT_TRUE(malformed);
  EXPECT_FALSE(execute_call(ctx_, {1, {i(1)}}, {}, malformed));  // too few
  EXPECT_TRUE(malformed);
  EXPECT_FALSE(execute_call(ctx_, {3, {t("x")}}, {}, malformed));  // wrong type
  EXPECT_TRUE(malformed);
  EXPECT_FALSE(execute_call(ctx_, {3, {i(1LL << 40)}}, {}, malformed));  // outside i32
  EXPECT_TRUE(malformed);
}

TEST(RefgoCmdResult, Parsing) {
  EXPECT_EQ(refgo_cmd_result("TS", "TS\r\n2\r\n>"), Value::integer(2));
  EXPECT_EQ(refgo_cmd_result("TP", "TP\r\n-7200\r\n>"), Value::integer(-7200));
  EXPECT_EQ(refgo_cmd_result("TPSR", "TPSR\r\n0000010a\r\n>"), Value::integer(0x10A));
  EXPECT_EQ(refgo_cmd_result("G5000", "G5000\r\n>"), Value::text(""));
  EXPECT_EQ(refgo_cmd_result("X", ">"), Value::none());
  EXPECT_EQ(refgo_cmd_result("OR1234,0", "OR1234,0\r\nOR1234,0,ERROR,06020000h\r\n>"), Value::none());
}

}  // namespace
}  // namespace mcemu::scripting
