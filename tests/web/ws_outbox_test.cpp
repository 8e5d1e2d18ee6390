// The outbound queue policy of a WebSocket client (web.md §10.4).
#include "web/api/ws_outbox.hpp"

#include <gtest/gtest.h>

namespace mcemu::web::api {
namespace {

WsOutbox::Message msg(std::string s) { return std::make_shared<const std::string>(std::move(s)); }

std::vector<std::string> drain(WsOutbox& box) {
  std::vector<std::string> out;
  while (auto m = box.pop()) out.push_back(*m);
  return out;
}

TEST(WsOutbox, EmptyPopsNull) {
  WsOutbox box;
  EXPECT_TRUE(box.empty());
  EXPECT_EQ(box.pop(), nullptr);
}

TEST(WsOutbox, FifoForOrdinaryMessages) {
  WsOutbox box;
  ASSERT_TRUE(box.push(msg("hello")));
  ASSERT_TRUE(box.push(msg("t1")));
  ASSERT_TRUE(box.push(msg("u1")));
  EXPECT_EQ(drain(box), (std::vector<std::string>{"hello", "t1", "u1"}));
  EXPECT_EQ(box.queued_bytes(), 0U);
}

TEST(WsOutbox, NewestStatusReplacesUnsentOneInPlace) {
  WsOutbox box;
  ASSERT_TRUE(box.push(msg("hello")));
  box.push_status(msg("s1"));
  ASSERT_TRUE(box.push(msg("t1")));
  box.push_status(msg("s2"));
  box.push_status(msg("s3"));
  EXPECT_EQ(box.size(), 3U);
  EXPECT_EQ(drain(box), (std::vector<std::string>{"hello", "s3", "t1"}));
}

TEST(WsOutbox, StatusAfterTheUnsentOneWasTakenIsQueuedAgain) {
  WsOutbox box;
  box.push_status(msg("s1"));
  EXPECT_EQ(*box.pop(), "s1");
  box.push_status(msg("s2"));
  ASSERT_TRUE(box.push(msg("t1")));
  box.push_status(msg("s3"));
  EXPECT_EQ(drain(box), (std::vector<std::string>{"s3", "t1"}));
}

TEST(WsOutbox, StatusNeverCountsAgainstTheLimit) {
  WsOutbox box(10);
  for (int i = 0; i < 100; ++i) box.push_status(msg(std::string(1000, 's')));
  EXPECT_EQ(box.queued_bytes(), 0U);
  EXPECT_TRUE(box.push(msg(std::string(10, 'x'))));
}

struct LimitCase {
  std::size_t limit;
  std::vector<std::size_t> sizes;
  std::size_t accepted;  // how many of `sizes` are queued before the first refusal
};

class WsOutboxLimit : public ::testing::TestWithParam<LimitCase> {};

TEST_P(WsOutboxLimit, RefusesTheMessageThatWouldExceedIt) {
  const auto& c = GetParam();
  WsOutbox box(c.limit);
  std::size_t accepted = 0;
  for (auto n : c.sizes) {
    if (!box.push(msg(std::string(n, 'x')))) break;
    ++accepted;
  }
  EXPECT_EQ(accepted, c.accepted);
  EXPECT_LE(box.queued_bytes(), c.limit);
}

INSTANTIATE_TEST_SUITE_P(Table, WsOutboxLimit,
                         ::testing::Values(LimitCase{100, {50, 50}, 2}, LimitCase{100, {50, 50, 1}, 2},
                                           LimitCase{100, {101}, 0}, LimitCase{100, {100}, 1},
                                           LimitCase{100, {0, 0, 100, 0}, 4},
                                           LimitCase{1024 * 1024, {512 * 1024, 512 * 1024, 1}, 2}));

TEST(WsOutbox, PoppingFreesRoom) {
  WsOutbox box(100);
  ASSERT_TRUE(box.push(msg(std::string(60, 'a'))));
  EXPECT_FALSE(box.push(msg(std::string(60, 'b'))));
  EXPECT_EQ(box.pop()->size(), 60U);
  EXPECT_TRUE(box.push(msg(std::string(60, 'b'))));
  EXPECT_EQ(box.queued_bytes(), 60U);
}

TEST(WsOutbox, DefaultLimitIsOneMiB) { EXPECT_EQ(WsOutbox{}.limit(), 1024U * 1024U); }

TEST(WsOutbox, SharedMessageIsNotCopied) {
  WsOutbox a;
  WsOutbox b;
  auto m = msg("snapshot");
  a.push_status(m);
  b.push_status(m);
  EXPECT_EQ(a.pop().get(), m.get());
  EXPECT_EQ(b.pop().get(), m.get());
}

}  // namespace
}  // namespace mcemu::web::api
