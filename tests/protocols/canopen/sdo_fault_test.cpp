// Fault injection in the node (slcan-canopen.md §11.3): slcan.sdoAbort at each phase of every kind
// of transfer, slcan.sdoNoReply, slcan.heartbeatStop. The hooks here behave like one injection with
// count 1 (the server asks web/api/transport_faults.hpp); after it the node answers normally again.
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

constexpr std::uint32_t k_code = 0x08000020;  // "cannot be stored": any code the test names

struct AbortCase {
  const char* name;
  std::uint16_t index;
  std::uint8_t sub;
  SdoFaultPhase phase;
  std::vector<Exchange> steps;  // the transfer with the fault, then exchanges after it
  bool consumed = true;         // the transfer had that phase (else the injection is still there)
};

// A one-occurrence injection: answers `code` the first time (index, sub, phase) match.
struct OneAbort {
  std::uint16_t index;
  std::uint8_t sub;
  SdoFaultPhase phase;
  int taken = 0;
  SdoFaults hooks() {
    SdoFaults f;
    f.abort = [this](std::uint16_t i, std::uint8_t s, SdoFaultPhase p) -> std::optional<std::uint32_t> {
      if (taken > 0 || i != index || s != sub || p != phase) return std::nullopt;
      ++taken;
      return k_code;
    };
    return f;
  }
};

class SdoAbortFault : public ::testing::TestWithParam<AbortCase> {};

TEST_P(SdoAbortFault, AbortsAtThatPhaseAndTheNodeStaysUsable) {
  const auto& c = GetParam();
  Harness h;
  h.boot();
  OneAbort fault{c.index, c.sub, c.phase};
  Node::Faults nf;
  nf.sdo = fault.hooks();
  h.node->set_faults(std::move(nf));
  for (const auto& s : c.steps) EXPECT_EQ(h.send(s.request), s.response) << s.request;
  EXPECT_EQ(fault.taken, c.consumed ? 1 : 0);
  // The node answers the next transfer normally.
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
}

const std::string k_abort_6041 = abort_line(0x6041, 0, k_code);
const std::string k_abort_6040 = abort_line(0x6040, 0, k_code);
const std::string k_abort_607a = abort_line(0x607A, 0, k_code);
const std::string k_abort_1008 = abort_line(0x1008, 0, k_code);

INSTANTIATE_TEST_SUITE_P(
    Phases, SdoAbortFault,
    ::testing::Values(
        AbortCase{
            "expedited_upload_initiate", 0x6041, 0, SdoFaultPhase::initiate, {{"t63284041600000000000", k_abort_6041}}},
        AbortCase{"expedited_upload_end", 0x6041, 0, SdoFaultPhase::end, {{"t63284041600000000000", k_abort_6041}}},
        AbortCase{"expedited_upload_has_no_segment",
                  0x6041,
                  0,
                  SdoFaultPhase::segment,
                  {{"t63284041600000000000", "t5B284B41600040000000\r"}},
                  false},
        AbortCase{"other_sub_untouched",
                  0x6041,
                  1,
                  SdoFaultPhase::initiate,
                  {{"t63284041600000000000", "t5B284B41600040000000\r"}},
                  false},
        // Downloads: the OD is not written (the read after it shows the old value).
        AbortCase{"expedited_download_initiate",
                  0x6040,
                  0,
                  SdoFaultPhase::initiate,
                  {{"t63282B4060000F000000", k_abort_6040}, {"t63284040600000000000", "t5B284B40600000000000\r"}}},
        AbortCase{"expedited_download_end",
                  0x6040,
                  0,
                  SdoFaultPhase::end,
                  {{"t63282B4060000F000000", k_abort_6040}, {"t63284040600000000000", "t5B284B40600000000000\r"}}},
        AbortCase{"segmented_upload_segment",
                  0x1008,
                  0,
                  SdoFaultPhase::segment,
                  {{"t63284008100000000000", "t5B28410810000C000000\r"}, {"t63286000000000000000", k_abort_1008}}},
        AbortCase{"segmented_upload_end",
                  0x1008,
                  0,
                  SdoFaultPhase::end,
                  {{"t63284008100000000000", "t5B28410810000C000000\r"},
                   {"t63286000000000000000", "t5B28004D433334395F45\r"},
                   {"t63287000000000000000", k_abort_1008}}},
        AbortCase{"segmented_download_segment",
                  0x607A,
                  0,
                  SdoFaultPhase::segment,
                  {{"t6328217A600004000000", "t5B28607A600000000000\r"},
                   {"t63280730750000000000", k_abort_607a},
                   {"t6328407A600000000000", "t5B28437A600000000000\r"}}},
        AbortCase{"segmented_download_end",
                  0x607A,
                  0,
                  SdoFaultPhase::end,
                  {{"t6328217A600004000000", "t5B28607A600000000000\r"},
                   {"t63280730750000000000", k_abort_607a},
                   {"t6328407A600000000000", "t5B28437A600000000000\r"}}},
        AbortCase{
            "block_download_initiate", 0x607A, 0, SdoFaultPhase::initiate, {{"t6328C67A600004000000", k_abort_607a}}},
        AbortCase{"block_download_segment",
                  0x607A,
                  0,
                  SdoFaultPhase::segment,
                  {{"t6328C67A600004000000", "t5B28A47A60007F000000\r"},
                   {"t63288130750000000000", k_abort_607a},
                   {"t6328407A600000000000", "t5B28437A600000000000\r"}}},
        AbortCase{"block_download_end",
                  0x607A,
                  0,
                  SdoFaultPhase::end,
                  {{"t6328C67A600004000000", "t5B28A47A60007F000000\r"},
                   {"t63288130750000000000", "t5B28A2017F0000000000\r"},
                   {"t6328CD111F0000000000", k_abort_607a},
                   {"t6328407A600000000000", "t5B28437A600000000000\r"}}},
        AbortCase{"block_upload_segment",
                  0x1008,
                  0,
                  SdoFaultPhase::segment,
                  {{"t6328A40810007F000000", "t5B28C60810000C000000\r"}, {"t6328A300000000000000", k_abort_1008}}},
        AbortCase{"block_upload_end",
                  0x1008,
                  0,
                  SdoFaultPhase::end,
                  {{"t6328A40810007F000000", "t5B28C60810000C000000\r"},
                   {"t6328A300000000000000", "t5B28014D433334395F45\rt5B288254485F52450000\r"},
                   {"t6328A2027F0000000000", k_abort_1008}}}),
    [](const ::testing::TestParamInfo<AbortCase>& i) { return std::string(i.param.name); });

// slcan.sdoNoReply for index (nullopt = every index), count 1.
struct OneNoReply {
  std::optional<std::uint16_t> index;
  int taken = 0;
  SdoFaults hooks() {
    SdoFaults f;
    f.no_reply = [this](std::uint16_t i) {
      if (taken > 0 || (index && *index != i)) return false;
      ++taken;
      return true;
    };
    return f;
  }
};

TEST(SdoNoReply, SwallowsOneResponseThenTheNodeAnswers) {
  Harness h;
  h.boot();
  OneNoReply fault{0x6041};
  Node::Faults nf;
  nf.sdo = fault.hooks();
  h.node->set_faults(std::move(nf));
  EXPECT_EQ(h.send("t63284000100000000000"), "t5B284300100092010200\r") << "1000h does not match";
  EXPECT_EQ(h.send("t63284041600000000000"), "") << "swallowed";
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  EXPECT_EQ(fault.taken, 1);
}

TEST(SdoNoReply, ASwallowedDownloadIsStillWritten) {
  // The lost frame is the response: the request reached the node (a retry writes again).
  Harness h;
  h.boot();
  OneNoReply fault{std::nullopt};
  Node::Faults nf;
  nf.sdo = fault.hooks();
  h.node->set_faults(std::move(nf));
  EXPECT_EQ(h.send("t6328237A600030750000"), "");
  EXPECT_EQ(h.number(0x607A, 0), 30000);
}

TEST(SdoNoReply, ASwallowedSegmentedInitiateLeavesTheServerUsable) {
  Harness h;
  h.boot();
  OneNoReply fault{0x1008};
  Node::Faults nf;
  nf.sdo = fault.hooks();
  h.node->set_faults(std::move(nf));
  EXPECT_EQ(h.send("t63284008100000000000"), "");
  // The client times out and starts again: a new initiate replaces the old transfer (§6.7).
  EXPECT_EQ(h.send("t63284008100000000000"), "t5B28410810000C000000\r");
  EXPECT_EQ(h.send("t63286000000000000000"), "t5B28004D433334395F45\r");
}

TEST(SdoNoReply, RequestsWithoutAnAnswerDoNotUseTheInjection) {
  Harness h;
  h.boot();
  OneNoReply fault{std::nullopt};
  Node::Faults nf;
  nf.sdo = fault.hooks();
  h.node->set_faults(std::move(nf));
  EXPECT_EQ(h.send("t63288000000000000000"), "") << "a client abort has no answer";
  EXPECT_EQ(fault.taken, 0);
}

TEST(HeartbeatStop, SuppressesHeartbeatsWhileTheHookSaysSo) {
  Harness h;
  h.boot();
  h.send("t63282B17100064000000");  // 1017h = 100 ms
  int stopped = 0;
  bool active = true;
  Node::Faults nf;
  nf.heartbeat_stop = [&] {
    if (!active) return false;
    ++stopped;
    return true;
  };
  h.node->set_faults(std::move(nf));
  EXPECT_EQ(h.wait(350ms), "");
  EXPECT_EQ(stopped, 3) << "one occurrence per heartbeat that was due";
  active = false;
  EXPECT_EQ(h.wait(100ms), "t73217F\r") << "the period ran on";
}

}  // namespace
}  // namespace mcemu::canopen::test
