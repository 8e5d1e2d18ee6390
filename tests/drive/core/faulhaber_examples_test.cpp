// AN165 Examples A and B (faulhaber.md §10) as the drive core sees them: the programs' main loops
// transcribed into C++, one loop pass per simulated millisecond, every SETOBJ an OD write with
// origin script. The BASIC interpreter is not involved; this checks that the drive differences of
// §7 carry both programs: 6060h inside the write, 0x0F from Ready to switch on, bit 10 dropping
// on every set-point (also to the actual position), homing 17 on 2310h.01.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/drive/core/core_fixture.hpp"

namespace mcemu::core {
namespace {

using test::Drive;

struct Script {
  Drive& d;
  void setobj(std::uint16_t index, std::uint8_t sub, std::int64_t v) {
    ASSERT_EQ(d.od.write(index, sub, od::Value{v}, od::Origin::script), od::AbortCode::none)
        << std::hex << index << "." << int(sub);
    d.collect();
  }
  std::int64_t getobj(std::uint16_t index, std::uint8_t sub) { return *d.od.read_number(index, sub); }
};

TEST(FaulhaberExamples, ExampleAHomesOnTheNegativeLimitSwitchAndSteps) {
  Drive d("FH_MC5005");
  Script b{d};
  d.step();
  // :Init
  b.setobj(0x2310, 0x01, 4);
  b.setobj(0x2310, 0x02, 0);
  b.setobj(0x2310, 0x10, 0);
  b.setobj(0x2310, 0x11, 0);
  std::int64_t p = 10000, i = 1, r = 10, q = 10;
  (void)i;
  b.setobj(0x6083, 0, r);
  b.setobj(0x6084, 0, r);
  b.setobj(0x6060, 0, 6);
  b.setobj(0x6040, 0, 0);
  int y = 0, z = 0;
  d.core.set_external_input_level(1, true);  // DigIn1: enable
  std::vector<std::int64_t> ramps;
  int moves = 0;
  bool homed = false;
  for (std::uint64_t ms = 0; ms < 600000 && moves < 10; ++ms) {
    // the fixture's switch: DigIn3 while the observed position is at or below −20000 (§10)
    d.core.set_external_input_level(3, d.read(0x6064) <= -20000);
    // :MainLoop
    const std::int64_t a = b.getobj(0x2311, 0x01);
    const std::int64_t s = b.getobj(0x6041, 0x00);
    const bool m = (s & 0x1000) > 0;
    const bool n = (s & 0x0400) > 0;
    if (y == 0) {
      if ((s & 0x6F) == 0x40) y = 1;
    } else if (y == 1) {
      if (a & 0x01) {
        b.setobj(0x6040, 0, 0x06);
        b.setobj(0x6040, 0, 0x0F);
        y = 2;
      }
    } else if (y == 2) {
      if ((s & 0x6F) == 0x27) y = 3;
    } else if (y == 3) {
      if (a & 0x02) {
        b.setobj(0x6040, 0, 0);
        y = 0;
      }
    }
    if (y == 3) {
      if (z == 0) {
        b.setobj(0x6098, 0, 17);
        b.setobj(0x6040, 0, 0x1F);
        z = 1;
      } else if (z == 1) {
        if (m) {
          homed = true;
          EXPECT_NE(s & 0x0400, 0) << "homing complete: bits 12 and 10";
          b.setobj(0x6040, 0, 0x0F);
          b.setobj(0x6060, 0, 1);
          z = 2;
        }
      } else if (z == 2) {
        b.setobj(0x607A, 0, p);
        b.setobj(0x6040, 0, 0x1F);
        z = 3;
      } else if (z == 3) {
        b.setobj(0x6040, 0, 0x0F);
        if (!n) z = 4;
      } else if (z == 4) {
        if (n) {
          EXPECT_LE(std::llabs(d.read(0x6064) - d.read(0x607A)), d.read(0x6067)) << "move " << moves;
          ++moves;
          p = -p;
          r = r + q;
          if (r == 500 || r == 10) q = -q;
          b.setobj(0x6083, 0, r);
          b.setobj(0x6084, 0, r);
          ramps.push_back(r);
          z = 2;
        }
      }
    }
    d.step();
  }
  EXPECT_TRUE(homed);
  EXPECT_EQ(moves, 10);
  EXPECT_EQ(ramps, (std::vector<std::int64_t>{20, 30, 40, 50, 60, 70, 80, 90, 100, 110}));
  EXPECT_TRUE(d.of<Emcy>().empty());
  // DigIn1 low, DigIn2 high: disabled within 10 ms and stays so
  d.core.set_external_input_level(1, false);
  d.core.set_external_input_level(2, true);
  for (int ms = 0; ms < 10; ++ms) {
    const std::int64_t a = b.getobj(0x2311, 0x01);
    if (y == 3 && (a & 0x02)) {
      b.setobj(0x6040, 0, 0);
      y = 0;
    }
    d.step();
  }
  EXPECT_EQ(d.sw() & 0x6F, 0x40);
}

TEST(FaulhaberExamples, ExampleBCyclesThroughThreeTargets) {
  Drive d("FH_MC5005");
  Script b{d};
  d.step();
  b.setobj(0x6060, 0, 1);
  b.setobj(0x2310, 0x01, 0);
  b.setobj(0x2310, 0x02, 0);
  b.setobj(0x6040, 0, 0);
  int y = 0, z = 0, moves = 0;
  std::uint64_t first_start = 0, first_reached = 0;
  struct Step {
    std::int64_t target, window_ms;
  };
  const Step steps[3] = {{0, 500}, {40000, 20}, {45000, 100}};
  std::uint64_t inside_since = 0;
  for (std::uint64_t ms = 0; ms < 120000 && moves < 9; ++ms) {
    const std::int64_t s = b.getobj(0x6041, 0);
    if (y == 0) {
      if ((s & 0x7F) == 0x40) {
        b.setobj(0x6040, 0, 0x06);
        b.setobj(0x6040, 0, 0x0F);
        y = 1;
      }
    } else if (y == 1) {
      if ((s & 0x7F) == 0x27) {
        y = 2;
        z = 0;
      }
    }
    if (y == 2) {
      const int k = z / 2;  // 0, 2, 4: start a move; 1, 3, 5: wait for the start; 2, 4, 6: in position
      if (z == 0 || (z % 2 == 0 && (s & 0x0400))) {
        if (z != 0) {
          ++moves;
          EXPECT_LE(std::llabs(d.read(0x6064) - d.read(0x607A)), d.read(0x6067));
          EXPECT_GE(d.core.time_ms() - inside_since, static_cast<std::uint64_t>(d.read(0x6068)));
          if (first_reached == 0) first_reached = d.core.time_ms();
        }
        const Step& next = steps[z == 6 ? 0 : k];
        if (z == 6) z = 0;
        b.setobj(0x607A, 0, next.target);
        b.setobj(0x6068, 0, next.window_ms);
        b.setobj(0x6040, 0, 0x1F);
        EXPECT_EQ(d.sw() & 0x0400, 0) << "bit 10 drops inside the 0x1F write";
        if (first_start == 0) first_start = d.core.time_ms();
        ++z;
      } else if (z % 2 == 1 && !(s & 0x0400)) {
        ++z;
        b.setobj(0x6040, 0, 0x0F);
      }
    }
    d.step();
    const bool inside = std::llabs(d.read(0x6064) - d.read(0x607A)) <= d.read(0x6067);
    if (!inside) inside_since = d.core.time_ms() + 1;
  }
  EXPECT_EQ(moves, 9);
  // the first set-point equals the actual position 0: bit 10 rises 500 ms after the 0x1F write
  EXPECT_GE(first_reached - first_start, 500u);
  EXPECT_LE(first_reached - first_start, 503u);
}

}  // namespace
}  // namespace mcemu::core
