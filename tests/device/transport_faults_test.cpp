// The transport-side fault decisions (web.md §9, slcan-canopen.md §11.3) as the network adapters
// see them: matching, counting down `count`, one-shot actions, removal reports.
#include "device/transport_faults.hpp"

#include <gtest/gtest.h>

namespace mcemu::device {
namespace {

TransportFault make(std::string id, TransportKind k, std::optional<std::uint64_t> count = std::nullopt) {
  TransportFault f;
  f.id = std::move(id);
  f.kind = k;
  f.remaining = count;
  return f;
}

struct Fixture {
  Fixture() {
    t.set_removed_listener(
        [this](const std::string& id, std::string_view reason) { removed.push_back(id + ":" + std::string(reason)); });
    t.set_action_listener([this] { ++notified; });
  }
  TransportFaults t;
  std::vector<std::string> removed;
  int notified = 0;
};

// Every "take" kind: without an injection nothing happens; with count 2 exactly two occurrences.
struct TakeCase {
  const char* name;
  TransportKind kind;
  std::function<bool(TransportFaults&)> take;  // true = the occurrence was affected
};

class Takes : public ::testing::TestWithParam<TakeCase> {};

TEST_P(Takes, CountsDownAndRemovesItself) {
  const auto& c = GetParam();
  Fixture f;
  EXPECT_FALSE(c.take(f.t)) << "nothing injected";
  auto fault = make("f1", c.kind, 2);
  fault.ms = 250;
  fault.status = 503;
  f.t.add(fault);
  EXPECT_TRUE(c.take(f.t));
  EXPECT_TRUE(f.removed.empty());
  EXPECT_TRUE(c.take(f.t));
  EXPECT_EQ(f.removed, std::vector<std::string>{"f1:count"});
  EXPECT_FALSE(c.take(f.t)) << "used up";
  EXPECT_TRUE(f.t.active().empty());
}

TEST_P(Takes, WithoutCountItStaysUntilRemoved) {
  const auto& c = GetParam();
  Fixture f;
  auto fault = make("f1", c.kind);
  fault.ms = 250;
  fault.status = 503;
  f.t.add(fault);
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(c.take(f.t));
  EXPECT_TRUE(f.t.remove("f1"));
  EXPECT_FALSE(c.take(f.t));
  EXPECT_TRUE(f.removed.empty()) << "remove() does not report (the caller does)";
}

INSTANTIATE_TEST_SUITE_P(
    Kinds, Takes,
    ::testing::Values(
        TakeCase{"refgo.noReply", TransportKind::refgo_no_reply,
                 [](TransportFaults& tf) { return tf.take_refgo_no_reply(); }},
        TakeCase{"refgo.delay", TransportKind::refgo_delay,
                 [](TransportFaults& tf) { return tf.refgo_delay_ms() == std::optional<std::uint32_t>(250); }},
        TakeCase{"udp.drop", TransportKind::udp_drop, [](TransportFaults& tf) { return tf.take_udp_drop(); }},
        TakeCase{"http.error", TransportKind::http_error,
                 [](TransportFaults& tf) { return tf.take_http_error("/index.html") == std::optional<int>(503); }},
        TakeCase{"slcan.dropTx", TransportKind::slcan_drop_tx,
                 [](TransportFaults& tf) { return tf.slcan_drop(0x1B2); }},
        TakeCase{"slcan.delayTx", TransportKind::slcan_delay_tx,
                 [](TransportFaults& tf) { return tf.slcan_delay_ms() == std::optional<std::uint32_t>(250); }},
        TakeCase{"slcan.sdoNoReply", TransportKind::slcan_sdo_no_reply,
                 [](TransportFaults& tf) { return tf.take_sdo_no_reply(0x6041); }},
        TakeCase{"slcan.heartbeatStop", TransportKind::slcan_heartbeat_stop,
                 [](TransportFaults& tf) { return tf.take_heartbeat_stop(); }},
        TakeCase{"slcan.bel", TransportKind::slcan_bel, [](TransportFaults& tf) { return tf.take_slcan_bel(); }}));

TEST(TransportFaults, KindsDoNotAnswerForEachOther) {
  Fixture f;
  f.t.add(make("f1", TransportKind::refgo_no_reply));
  EXPECT_FALSE(f.t.take_udp_drop());
  EXPECT_FALSE(f.t.refgo_delay_ms());
  EXPECT_FALSE(f.t.take_slcan_bel());
  EXPECT_FALSE(f.t.slcan_drop(0x80));
  EXPECT_TRUE(f.t.take_refgo_no_reply());
}

TEST(TransportFaults, DropTxMatchesItsIdentifierOnly) {
  Fixture f;
  auto d = make("f1", TransportKind::slcan_drop_tx, 1);
  d.cob_id = 0x1B2;
  f.t.add(d);
  EXPECT_FALSE(f.t.slcan_drop(0x732)) << "heartbeat passes";
  EXPECT_TRUE(f.t.slcan_drop(0x1B2));
  EXPECT_FALSE(f.t.slcan_drop(0x1B2)) << "count 1 used";
}

TEST(TransportFaults, HttpErrorMatchesThePathPrefix) {
  Fixture f;
  auto e = make("f1", TransportKind::http_error);
  e.status = 500;
  e.path = "/servo";
  f.t.add(e);
  EXPECT_FALSE(f.t.take_http_error("/index.html"));
  EXPECT_EQ(f.t.take_http_error("/servo.html"), 500);
}

TEST(TransportFaults, SdoAbortMatchesIndexSubAndPhase) {
  Fixture f;
  auto a = make("f1", TransportKind::slcan_sdo_abort, 1);
  a.index = 0x1008;
  a.sub = 0;
  a.abort_code = 0x08000000;
  a.phase = SdoPhase::segment;
  f.t.add(a);
  EXPECT_FALSE(f.t.slcan_sdo_abort(0x1008, 0, SdoPhase::initiate));
  EXPECT_FALSE(f.t.slcan_sdo_abort(0x1008, 1, SdoPhase::segment));
  EXPECT_FALSE(f.t.slcan_sdo_abort(0x1009, 0, SdoPhase::segment));
  const auto plan = f.t.slcan_sdo_abort(0x1008, 0, SdoPhase::segment);
  ASSERT_TRUE(plan);
  EXPECT_EQ(plan->code, 0x08000000u);
  EXPECT_FALSE(f.t.slcan_sdo_abort(0x1008, 0, SdoPhase::segment)) << "the next transfer is served normally";
  EXPECT_EQ(f.removed, std::vector<std::string>{"f1:count"});
}

TEST(TransportFaults, SdoNoReplyWithAndWithoutIndex) {
  Fixture f;
  auto n = make("f1", TransportKind::slcan_sdo_no_reply);
  n.index = 0x6041;
  f.t.add(n);
  EXPECT_FALSE(f.t.take_sdo_no_reply(0x6040));
  EXPECT_TRUE(f.t.take_sdo_no_reply(0x6041));
  f.t.add(make("f2", TransportKind::slcan_sdo_no_reply));
  EXPECT_TRUE(f.t.take_sdo_no_reply(0x6040));
}

TEST(TransportFaults, OldestMatchingInjectionIsUsedFirst) {
  Fixture f;
  auto a = make("f1", TransportKind::refgo_delay, 1);
  a.ms = 10;
  auto b = make("f2", TransportKind::refgo_delay);
  b.ms = 20;
  f.t.add(a);
  f.t.add(b);
  EXPECT_EQ(f.t.refgo_delay_ms(), 10u);
  EXPECT_EQ(f.t.refgo_delay_ms(), 20u);
  EXPECT_EQ(f.t.refgo_delay_ms(), 20u);
}

TEST(TransportFaults, OneShotActionsAreQueuedOnceAndDrained) {
  Fixture f;
  auto raw = make("f1", TransportKind::slcan_raw_tx, 5);
  raw.text = "t12\r";
  f.t.add(raw);
  f.t.add(make("f2", TransportKind::refgo_disconnect));
  f.t.add(make("f3", TransportKind::slcan_disconnect));
  EXPECT_EQ(f.notified, 3);
  EXPECT_TRUE(f.t.has_actions());
  EXPECT_EQ(f.t.active().size(), 3u) << "listed until performed";
  const auto actions = f.t.drain_actions();
  ASSERT_EQ(actions.size(), 3u);
  EXPECT_EQ(actions[0].kind, TransportKind::slcan_raw_tx);
  EXPECT_EQ(actions[0].text, "t12\r");
  EXPECT_EQ(actions[1].kind, TransportKind::refgo_disconnect);
  EXPECT_EQ(actions[2].kind, TransportKind::slcan_disconnect);
  EXPECT_EQ(f.removed, (std::vector<std::string>{"f1:done", "f2:done", "f3:done"}));
  EXPECT_TRUE(f.t.drain_actions().empty());
  EXPECT_TRUE(f.t.active().empty());
}

TEST(TransportFaults, RemovingAPendingOneShotCancelsItsAction) {
  Fixture f;
  f.t.add(make("f1", TransportKind::refgo_disconnect));
  EXPECT_TRUE(f.t.remove("f1"));
  EXPECT_TRUE(f.t.drain_actions().empty());
  EXPECT_FALSE(f.t.remove("f1"));
}

}  // namespace
}  // namespace mcemu::device
