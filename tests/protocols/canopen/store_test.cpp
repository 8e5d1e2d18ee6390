// Store/Restore over SDO (slcan-canopen.md §6.1, §10; persistence.md §3, §4, §12; conformance
// OTH-01 … OTH-07 at unit level). A stand-in for persistence's hooks answers `pending` and lets the
// test decide when the "file is durable".
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

struct FakePersistence {
  std::vector<od::Done> waiting;
  bool operation_enabled = false;
  bool complete_inside_the_hook = false;
  int stores = 0;

  void install(od::ObjectDictionary& od) {
    for (std::uint8_t s = 1; s <= 3; ++s) {
      od.on_write(0x1010, s, [this](od::WriteRequest& req) { return request(req, 0x65766173, false); });
      od.on_write(0x1011, s, [this](od::WriteRequest& req) { return request(req, 0x64616F6C, true); });
    }
  }
  // noinline: GCC 12 reports a false -Wfree-nonheap-object for the variant assignment when inlined
  [[gnu::noinline]] od::AbortCode request(od::WriteRequest& req, std::int64_t signature, bool restore) {
    if (std::get<std::int64_t>(req.value) != signature) return od::AbortCode::cannot_store;
    if (restore && operation_enabled) return od::AbortCode::device_state;
    ++stores;
    req.value.emplace<std::int64_t>(1);  // the value written is not kept
    if (complete_inside_the_hook) {
      (*req.done)(od::AbortCode::none);
      return od::AbortCode::pending;
    }
    waiting.push_back(std::move(*req.done));
    return od::AbortCode::pending;
  }
  void finish(od::AbortCode result = od::AbortCode::none) {
    auto d = std::move(waiting.front());
    waiting.erase(waiting.begin());
    d(result);
  }
};

struct StoreHarness : Harness {
  int wakes = 0;
  FakePersistence persistence;
  StoreHarness() : Harness("MC349", {}, false, hooks()) { persistence.install(*od); }
  Node::Hooks hooks() {
    Node::Hooks k;
    k.wake = [this] { ++wakes; };
    return k;
  }
};

TEST(Store, ResponseOnlyWhenDurable) {  // OTH-01, §6.10 "store all"
  StoreHarness h;
  h.boot();
  EXPECT_EQ(h.send("t63282310100173617665"), "");
  EXPECT_EQ(h.wait(5s), "");  // the server timeout does not run
  h.persistence.finish();
  EXPECT_EQ(h.wakes, 1);
  ASSERT_TRUE(h.node->next_deadline());
  EXPECT_LE(*h.node->next_deadline(), h.now);  // due at once
  EXPECT_EQ(h.wait(0ms), "t5B286010100100000000\r");
  EXPECT_EQ(h.send("t63284010100100000000"), "t5B284310100101000000\r");  // OTH-07: reads 1
}

TEST(Store, ClientAbortCancelsOnlyTheResponse) {  // OTH-01
  StoreHarness h;
  h.boot();
  h.send("t63282310100173617665");
  EXPECT_EQ(h.send("t63288000000000000405"), "");  // python-canopen's abort after 0.3 s
  h.persistence.finish();
  EXPECT_EQ(h.persistence.stores, 1);  // the store still completed
  EXPECT_EQ(h.wait(1s), "");           // and nothing is ever sent for it
}

TEST(Store, NewInitiateIsServedAndOldResponseDropped) {  // §6.1
  StoreHarness h;
  h.boot();
  h.send("t63282310100173617665");
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  h.persistence.finish();
  EXPECT_EQ(h.wait(1s), "");
  // a new store after a pending one is answered after its own completion
  h.send("t63282310100173617665");
  EXPECT_EQ(h.send("t63282310100273617665"), "");
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), "");
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), "t5B286010100200000000\r");
}

TEST(Store, OtherRequestsAbortWithUnknownCommand) {  // §6.1, §6.7
  StoreHarness h;
  h.boot();
  h.send("t63282310100173617665");
  EXPECT_EQ(h.send("t63286000000000000000"), abort_line(0x1010, 1, 0x05040001));
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), "");
}

TEST(Store, FailuresAndSignatures) {  // OTH-03, OTH-05, §6.10 "SAVE"
  StoreHarness h;
  h.boot();
  EXPECT_EQ(h.send("t63282310100153415645"), "t5B288010100120000008\r");
  EXPECT_EQ(h.send(sdo({0x23, 0x11, 0x10, 0x01, 's', 'a', 'v', 'e'})), abort_line(0x1011, 1, 0x08000020));
  h.persistence.operation_enabled = true;
  EXPECT_EQ(h.send("t6328231110016C6F6164"), abort_line(0x1011, 1, 0x08000022));
  h.persistence.operation_enabled = false;
  EXPECT_EQ(h.send("t6328231110016C6F6164"), "");
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), "t5B286011100100000000\r");  // §6.10 "restore"
  h.send("t63282310100373617665");
  h.persistence.finish(od::AbortCode::hardware_error);
  EXPECT_EQ(h.wait(0ms), abort_line(0x1010, 3, 0x06060000));
  EXPECT_EQ(h.send(sdo({0x2B, 0x10, 0x10, 0x01, 's', 'a'})), abort_line(0x1010, 1, 0x06070013));
}

TEST(Store, SegmentedAndBlockDownloadsAnswerLateToo) {
  StoreHarness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x21, 0x10, 0x10, 0x01, 4})), resp({0x60, 0x10, 0x10, 0x01}));
  EXPECT_EQ(h.send(sdo({0x07, 's', 'a', 'v', 'e'})), "");
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), resp({0x20}));
  EXPECT_EQ(h.send(sdo({0xC2, 0x10, 0x10, 0x01, 4})), resp({0xA0, 0x10, 0x10, 0x01, 127}));
  EXPECT_EQ(h.send(sdo({0x81, 's', 'a', 'v', 'e'})), resp({0xA2, 1, 127}));
  EXPECT_EQ(h.send(sdo({0xCD})), "");
  h.persistence.finish();
  EXPECT_EQ(h.wait(0ms), resp({0xA1}));
}

TEST(Store, CompletionInsideTheWriteIsAnsweredInTheSameCall) {
  StoreHarness h;
  h.persistence.complete_inside_the_hook = true;
  h.boot();
  EXPECT_EQ(h.send("t63282310100173617665"), "t5B286010100100000000\r");
}

TEST(Store, NodeDestroyedBeforeCompletionIsSafe) {
  StoreHarness h;
  h.boot();
  h.send("t63282310100173617665");
  h.node.reset();
  h.persistence.finish();  // must not touch the destroyed node
  SUCCEED();
}

}  // namespace
}  // namespace mcemu::canopen::test
