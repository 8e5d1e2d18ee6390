// TPSR, TS, TI and the reply formatting (refgo.md §3, §8, §9.3).
#include "protocols/refgo/status.hpp"

#include <gtest/gtest.h>

#include "protocols/refgo/reply.hpp"

namespace mcemu::refgo {
namespace {

struct StatusCase {
  std::uint16_t statusword;
  PowerState state;
  std::uint32_t tpsr;
  int ts;
};

class StatusTable : public ::testing::TestWithParam<StatusCase> {};

TEST_P(StatusTable, TpsrAndTs) {
  const auto& c = GetParam();
  EXPECT_EQ(power_state(c.statusword), c.state);
  EXPECT_EQ(tpsr(c.statusword), c.tpsr) << std::hex << c.statusword;
  EXPECT_EQ(simple_status(tpsr(c.statusword)), c.ts);
}

// Examples of refgo.md §8.1 with statuswords of drive-core.md §5.
INSTANTIATE_TEST_SUITE_P(
    Examples, StatusTable,
    ::testing::Values(StatusCase{0x0000, PowerState::nrtso, 0x002, 0}, StatusCase{0x0240, PowerState::sod, 0x002, 0},
                      StatusCase{0x0221, PowerState::rtso, 0x002, 0}, StatusCase{0x0223, PowerState::so, 0x102, 1},
                      StatusCase{0x0227, PowerState::oe, 0x102, 1},   // powered, target not reached
                      StatusCase{0x1327, PowerState::oe, 0x106, 2},   // moving, set-point acknowledged
                      StatusCase{0x0127, PowerState::oe, 0x106, 2},   // moving (MAN 127h)
                      StatusCase{0x0427, PowerState::oe, 0x10a, 1},   // in position (MAN 427h)
                      StatusCase{0x0207, PowerState::qsa, 0x102, 1},  // quick stop, standing
                      StatusCase{0x0107, PowerState::qsa, 0x106, 2},  // quick stop ramp
                      StatusCase{0x010F, PowerState::fra, 0x107, 9},  // fault reaction braking
                      StatusCase{0x000F, PowerState::fra, 0x103, 9},  // FRA at standstill
                      StatusCase{0x0008, PowerState::f, 0x003, 9},    // fault
                      StatusCase{0x0228, PowerState::f, 0x003, 9}));

TEST(Inputs, TellInputAndAll) {
  const std::uint32_t in1_in3 = (1U << 16) | (1U << 18);
  EXPECT_EQ(tell_inputs(in1_in3), "0005");
  EXPECT_EQ(tell_input(in1_in3, 1), "1");
  EXPECT_EQ(tell_input(in1_in3, 2), "0");
  EXPECT_EQ(tell_input(in1_in3, 3), "1");
  EXPECT_EQ(tell_inputs(0x3FFU << 16), "03ff");
  EXPECT_EQ(tell_inputs(0xFFFFFFFF), "03ff");
  EXPECT_EQ(tell_input(1U << 25, 10), "1");
  EXPECT_EQ(tell_inputs(0), "0000");
}

TEST(Format, Replies) {
  EXPECT_EQ(reply("PWC"), "PWC\r\n>");
  EXPECT_EQ(reply("TP", "-3658"), "TP\r\n-3658\r\n>");
  EXPECT_EQ(error_reply("OW6041,0,5", "OW6041,0,5", od::AbortCode::read_only),
            "OW6041,0,5\r\nOW6041,0,5,ERROR,06010002h\r\n>");
  EXPECT_EQ(hex8(0x10a), "0000010a");
  EXPECT_EQ(hex_h(0x427), "427h");
  EXPECT_EQ(hex_h(0), "0h");
  EXPECT_EQ(hex_h(static_cast<std::uint32_t>(-10)), "fffffff6h");
}

}  // namespace
}  // namespace mcemu::refgo
