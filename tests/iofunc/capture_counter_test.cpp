// Input functions 1–3 (iofunc.md §4.4–§4.6): tests IN-1, IN-2 and IN-3, row by row.
#include <gtest/gtest.h>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

TEST(Capture, In1CapturesOnBothEdgesWithoutRetrigger) {
  Rig rig;
  std::int64_t p1 = 0;
  std::int64_t c = 0;
  run_rows(rig, {
                    {"enable, move to 5000 (6067h = 10)",
                     [](Rig& r) {
                       r.W(0x6067, 0, 10);
                       r.enable();
                       r.move_to(5000);
                     },
                     [&](Rig& r) {
                       p1 = r.R(0x6064);
                       EXPECT_LE(std::llabs(p1 - 5000), 10);
                     }},
                    {"W(3511.01, 0x0102)", [](Rig& r) { r.W(0x3511, 1, 0x0102); },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3511, 3), 0);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                     }},
                    {"P(1,1), step(1)",
                     [&](Rig& r) {
                       p1 = r.R(0x6064);
                       r.P(1, true);
                       r.step();
                     },
                     [&](Rig& r) {
                       EXPECT_EQ(r.R(0x3511, 3), p1);
                       EXPECT_EQ(r.R(0x3511, 4), 0);
                     }},
                    {"W(3511.03, 0), step(100) with IN1 still high",
                     [](Rig& r) {
                       r.W(0x3511, 3, 0);
                       r.step(100);
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3511, 3), 0); }},
                    {"move to -5000; after 50 ms c = 6064h; P(1,0), step(1)",
                     [&](Rig& r) {
                       r.start_move(-5000);
                       r.step(50);
                       c = r.R(0x6064);
                       r.P(1, false);
                       r.step();
                     },
                     [&](Rig& r) {
                       EXPECT_NE(c, p1);  // the drive was moving: the capture is not a stale value
                       EXPECT_EQ(r.R(0x3511, 4), c);
                       EXPECT_EQ(r.R(0x3511, 3), 0);
                     }},
                });
}

TEST(Capture, In2UsesResultRegister2AndOnlyTheFallingByte) {
  Rig rig;
  std::int64_t p1 = 0;
  run_rows(rig, {
                    {"W(3512.01, 0x0002); drive at p1",
                     [&](Rig& r) {
                       r.W(0x3512, 1, 0x0002);
                       r.enable();
                       r.move_to(5000);
                       p1 = r.R(0x6064);
                     },
                     nullptr},
                    {"P(2,1), step(1)",
                     [](Rig& r) {
                       r.P(2, true);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3512, 4), 0); }},
                    {"P(2,0), step(1)",
                     [&](Rig& r) {
                       p1 = r.R(0x6064);
                       r.P(2, false);
                       r.step();
                     },
                     [&](Rig& r) {
                       EXPECT_NE(p1, 0);
                       EXPECT_EQ(r.R(0x3512, 4), p1);
                       EXPECT_EQ(r.R(0x3512, 3), 0);
                     }},
                });
}

TEST(Counter, In3CountsEveryEdgeWrapsAndSeesShortVirtualPulses) {
  Rig rig;
  run_rows(rig, {
                    {"W(3513.01, 0x0303), W(3513.03, 10)",
                     [](Rig& r) {
                       r.W(0x3513, 1, 0x0303);
                       r.W(0x3513, 3, 10);
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3513, 3), 10); }},
                    {"3 x (P(3,1), step(5), P(3,0), step(5))",
                     [](Rig& r) {
                       for (int i = 0; i < 3; ++i) {
                         r.P(3, true);
                         r.step(5);
                         r.P(3, false);
                         r.step(5);
                       }
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3513, 3), 16); }},
                    {"W(3513.03, 2147483647), P(3,1), step(1)",
                     [](Rig& r) {
                       r.W(0x3513, 3, 2147483647);
                       r.P(3, true);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3513, 3), -2147483648LL); }},
                    {"P(3,0), step(1)",
                     [](Rig& r) {
                       r.P(3, false);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3513, 3), -2147483647LL); }},
                    {"W(3510.01, 0x40000), W(3510.01, 0) between two steps, step(1)",
                     [](Rig& r) {
                       r.W(0x3510, 1, 0x40000);
                       r.W(0x3510, 1, 0);
                       r.step();
                     },
                     [](Rig& r) { EXPECT_EQ(r.R(0x3513, 3), -2147483645LL); }},
                    {"W(3513.01, 0x0300)", [](Rig& r) { r.W(0x3513, 1, 0x0300); },
                     [](Rig& r) {
                       EXPECT_EQ(r.R(0x3513, 3), 0);
                       EXPECT_EQ(r.R(0x3513, 4), 0);
                     }},
                });
}

// Writing .01 with the same value still clears the result registers (§4.1 "any write").
TEST(Counter, RewritingTheSameCodeClearsResults) {
  Rig rig;
  rig.W(0x3513, 1, 0x0300);
  rig.W(0x3513, 3, 7);
  rig.W(0x3513, 4, 9);
  rig.W(0x3513, 1, 0x0300);
  EXPECT_EQ(rig.R(0x3513, 3), 0);
  EXPECT_EQ(rig.R(0x3513, 4), 0);
}

// A code written while the input is high triggers nothing until the next edge (§3).
TEST(Counter, NewCodeWhileHighWaitsForTheNextEdge) {
  Rig rig;
  rig.P(3, true);
  rig.step(5);
  rig.W(0x3513, 1, 0x0300);
  rig.step(20);
  EXPECT_EQ(rig.R(0x3513, 3), 0);
  rig.P(3, false);
  rig.step();
  rig.P(3, true);
  rig.step();
  EXPECT_EQ(rig.R(0x3513, 3), 1);
}

}  // namespace
}  // namespace mcemu::iofunc::test
