// The per-unit fault decisions of web/api/fault_gates.hpp (web.md §9, slcan-canopen.md §11.3): a
// table of injections and the verdicts the next units get, and the order-keeping delay line.
#include "device/fault_gates.hpp"

#include <gtest/gtest.h>

#include <functional>

namespace mcemu::device {
namespace {

using namespace std::chrono_literals;
using Action = Verdict::Action;

TransportFault fault(std::string id, TransportKind kind, std::optional<std::uint64_t> count = std::nullopt) {
  TransportFault f;
  f.id = std::move(id);
  f.kind = kind;
  f.remaining = count;
  return f;
}

TransportFault with_ms(TransportFault f, std::uint32_t ms) {
  f.ms = ms;
  return f;
}

TransportFault with_cob(TransportFault f, std::uint32_t cob) {
  f.cob_id = cob;
  return f;
}

// What the next units get: (action, delay ms, deciding fault id).
struct Expect {
  Action action;
  int delay_ms = 0;
  const char* id = "";
};

struct Case {
  const char* name;
  std::vector<TransportFault> faults;
  std::function<Verdict(TransportFaults&)> ask;  // one unit
  std::vector<Expect> expect;                    // the verdicts of consecutive units
};

class Verdicts : public ::testing::TestWithParam<Case> {};

TEST_P(Verdicts, ConsecutiveUnits) {
  const auto& c = GetParam();
  TransportFaults t;
  std::vector<std::string> applied;
  t.set_applied_listener([&](const TransportFault& f) { applied.push_back(f.id); });
  for (const auto& f : c.faults) t.add(f);
  std::size_t decided = 0;
  for (std::size_t i = 0; i < c.expect.size(); ++i) {
    const Verdict v = c.ask(t);
    EXPECT_EQ(v.action, c.expect[i].action) << "unit " << i;
    EXPECT_EQ(v.delay, std::chrono::milliseconds(c.expect[i].delay_ms)) << "unit " << i;
    EXPECT_EQ(v.fault_id, c.expect[i].id) << "unit " << i;
    if (v.action != Action::send) ++decided;
  }
  EXPECT_EQ(applied.size(), decided) << "every application is reported once";
}

const auto refgo = [](TransportFaults& t) { return refgo_reply_verdict(t); };
const auto frame_1b2 = [](TransportFaults& t) { return node_frame_verdict(t, 0x1B2); };
const auto frame_732 = [](TransportFaults& t) { return node_frame_verdict(t, 0x732); };
const auto udp = [](TransportFaults& t) { return udp_datagram_verdict(t); };

INSTANTIATE_TEST_SUITE_P(
    Table, Verdicts,
    ::testing::Values(
        Case{"nothing_injected", {}, refgo, {{Action::send}, {Action::send}}},
        Case{"noReply_count_2",
             {fault("f1", TransportKind::refgo_no_reply, 2)},
             refgo,
             {{Action::drop, 0, "f1"}, {Action::drop, 0, "f1"}, {Action::send}}},
        Case{"noReply_without_count_stays",
             {fault("f1", TransportKind::refgo_no_reply)},
             refgo,
             {{Action::drop, 0, "f1"}, {Action::drop, 0, "f1"}, {Action::drop, 0, "f1"}}},
        Case{"delay_count_1",
             {with_ms(fault("f1", TransportKind::refgo_delay, 1), 250)},
             refgo,
             {{Action::delay, 250, "f1"}, {Action::send}}},
        Case{"noReply_before_delay",
             {with_ms(fault("f1", TransportKind::refgo_delay, 1), 250), fault("f2", TransportKind::refgo_no_reply, 1)},
             refgo,
             {{Action::drop, 0, "f2"}, {Action::delay, 250, "f1"}, {Action::send}}},
        Case{"oldest_delay_first",
             {with_ms(fault("f1", TransportKind::refgo_delay, 1), 100),
              with_ms(fault("f2", TransportKind::refgo_delay, 1), 900)},
             refgo,
             {{Action::delay, 100, "f1"}, {Action::delay, 900, "f2"}, {Action::send}}},
        Case{"refgo_ignores_other_kinds",
             {fault("f1", TransportKind::udp_drop), fault("f2", TransportKind::slcan_drop_tx)},
             refgo,
             {{Action::send}}},
        Case{"dropTx_any_frame",
             {fault("f1", TransportKind::slcan_drop_tx, 1)},
             frame_1b2,
             {{Action::drop, 0, "f1"}, {Action::send}}},
        Case{"dropTx_other_cob_untouched",
             {with_cob(fault("f1", TransportKind::slcan_drop_tx, 1), 0x1B2)},
             frame_732,
             {{Action::send}, {Action::send}}},
        Case{"dropTx_matching_cob",
             {with_cob(fault("f1", TransportKind::slcan_drop_tx, 1), 0x1B2)},
             frame_1b2,
             {{Action::drop, 0, "f1"}, {Action::send}}},
        Case{"delayTx",
             {with_ms(fault("f1", TransportKind::slcan_delay_tx, 2), 40)},
             frame_732,
             {{Action::delay, 40, "f1"}, {Action::delay, 40, "f1"}, {Action::send}}},
        Case{"dropTx_before_delayTx",
             {with_ms(fault("f1", TransportKind::slcan_delay_tx, 1), 40), fault("f2", TransportKind::slcan_drop_tx, 1)},
             frame_732,
             {{Action::drop, 0, "f2"}, {Action::delay, 40, "f1"}, {Action::send}}},
        Case{"udp_drop_count_3",
             {fault("f1", TransportKind::udp_drop, 3)},
             udp,
             {{Action::drop, 0, "f1"}, {Action::drop, 0, "f1"}, {Action::drop, 0, "f1"}, {Action::send}}},
        Case{"udp_ignores_refgo", {fault("f1", TransportKind::refgo_no_reply)}, udp, {{Action::send}}}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

TEST(VerdictText, NamesTheFault) {
  Verdict v;
  v.action = Action::drop;
  v.fault_id = "f3";
  v.kind = TransportKind::refgo_no_reply;
  EXPECT_EQ(verdict_text(v, "reply"), "reply not sent (fault f3 refgo.noReply)");
  v.action = Action::delay;
  v.delay = 200ms;
  v.kind = TransportKind::slcan_delay_tx;
  EXPECT_EQ(verdict_text(v, "frame t7321"), "frame t7321 held back 200 ms (fault f3 slcan.delayTx)");
}

TEST(DelayLine, PassesThroughWhenNothingWaits) {
  DelayLine<int> d;
  EXPECT_EQ(d.push(1, 100ms, 100ms), std::optional<int>(1));
  EXPECT_TRUE(d.empty());
  EXPECT_FALSE(d.next_due());
}

TEST(DelayLine, KeepsOrderBehindAHeldBackItem) {
  DelayLine<int> d;
  EXPECT_FALSE(d.push(1, 0ms, 300ms));  // delayed
  EXPECT_FALSE(d.push(2, 10ms, 10ms)) << "not delayed itself, but must not overtake 1";
  EXPECT_FALSE(d.push(3, 20ms, 400ms));
  EXPECT_EQ(d.next_due(), std::optional(300ms));
  EXPECT_TRUE(d.pop_due(299ms).empty());
  EXPECT_EQ(d.pop_due(300ms), (std::vector<int>{1, 2}));
  EXPECT_EQ(d.next_due(), std::optional(400ms));
  EXPECT_EQ(d.pop_due(400ms), (std::vector<int>{3}));
  EXPECT_TRUE(d.empty());
}

TEST(DelayLine, ReleasesInOrderEvenWhenALaterItemIsDueEarlier) {
  DelayLine<std::string> d;
  d.push("slow", 0ms, 500ms);
  d.push("fast", 0ms, 50ms);
  EXPECT_TRUE(d.pop_due(100ms).empty());
  EXPECT_EQ(d.pop_due(500ms), (std::vector<std::string>{"slow", "fast"}));
}

TEST(TransportFaultNames, EveryKindHasItsApiNameAndChannel) {
  struct Row {
    TransportKind kind;
    const char* name;
    trace::Channel channel;
  };
  const Row rows[] = {
      {TransportKind::refgo_no_reply, "refgo.noReply", trace::Channel::refgo},
      {TransportKind::refgo_delay, "refgo.delay", trace::Channel::refgo},
      {TransportKind::refgo_disconnect, "refgo.disconnect", trace::Channel::refgo},
      {TransportKind::udp_drop, "udp.drop", trace::Channel::udp},
      {TransportKind::http_error, "http.error", trace::Channel::http},
      {TransportKind::slcan_drop_tx, "slcan.dropTx", trace::Channel::slcan},
      {TransportKind::slcan_delay_tx, "slcan.delayTx", trace::Channel::slcan},
      {TransportKind::slcan_sdo_abort, "slcan.sdoAbort", trace::Channel::slcan},
      {TransportKind::slcan_sdo_no_reply, "slcan.sdoNoReply", trace::Channel::slcan},
      {TransportKind::slcan_heartbeat_stop, "slcan.heartbeatStop", trace::Channel::slcan},
      {TransportKind::slcan_raw_tx, "slcan.rawTx", trace::Channel::slcan},
      {TransportKind::slcan_bel, "slcan.bel", trace::Channel::slcan},
      {TransportKind::slcan_disconnect, "slcan.disconnect", trace::Channel::slcan},
  };
  for (const auto& r : rows) {
    EXPECT_EQ(to_string(r.kind), r.name);
    EXPECT_EQ(trace_channel(r.kind), r.channel) << r.name;
  }
  EXPECT_EQ(applied_text(fault("f9", TransportKind::slcan_bel)), "fault f9 slcan.bel applied");
}

TEST(TransportFaults, OneShotActionsAreReportedAsAppliedWhenDrained) {
  TransportFaults t;
  std::vector<std::string> applied;
  t.set_applied_listener([&](const TransportFault& f) { applied.push_back(f.id); });
  t.add(fault("f1", TransportKind::refgo_disconnect));
  t.add(fault("f2", TransportKind::slcan_raw_tx));
  EXPECT_TRUE(applied.empty()) << "applied when the server performs them";
  EXPECT_EQ(t.drain_actions().size(), 2u);
  EXPECT_EQ(applied, (std::vector<std::string>{"f1", "f2"}));
}

}  // namespace
}  // namespace mcemu::device
