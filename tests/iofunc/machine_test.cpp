// A stand-alone machine built only from I/O functions (the IO-EX pattern): IN1 → move to A,
// IN2 → move to B, OUT1/OUT2 bit-coded "position reached and OK" feedback, IN3 quick stop,
// IN4 software enable. Driven through the virtual inputs 3510h.01 as a PLC or RefGo would.
#include <gtest/gtest.h>

#include "tests/iofunc/io_fixture.hpp"

namespace mcemu::iofunc::test {
namespace {

constexpr std::int64_t k_a = 10000;
constexpr std::int64_t k_b = 30000;
constexpr std::int64_t k_enable = 1 << 19;  // IN4 in 3510h.01

struct Machine {
  Rig rig;
  std::int64_t virtual_inputs = 0;

  Machine() {
    rig.W(0x6067, 0, 10);
    rig.W(0x3511, 1, 0x0400);
    rig.W(0x3511, 8, k_a);
    rig.W(0x3511, 6, 1000);
    rig.W(0x3512, 1, 0x0400);
    rig.W(0x3512, 8, k_b);
    rig.W(0x3512, 6, 1000);
    rig.W(0x3513, 1, 0x0500);
    rig.W(0x3514, 1, 0x0900);
    for (std::uint16_t o : {0x3611, 0x3612}) {
      rig.W(o, 1, 6);
      rig.W(o, 2, 255);
      rig.W(o, 5, 20);
      rig.W(o, 6, 20);
    }
  }
  void set(std::int64_t bits, bool high) {
    virtual_inputs = high ? (virtual_inputs | bits) : (virtual_inputs & ~bits);
    rig.W(0x3510, 1, virtual_inputs);
  }
  void pulse(int n) {
    set(std::int64_t{1} << (15 + n), true);
    rig.step(10);
    set(std::int64_t{1} << (15 + n), false);
    rig.step(10);
  }
  std::pair<bool, bool> feedback() const { return {rig.out(1), rig.out(2)}; }
  void settle() {
    rig.until([&] { return rig.reached(); }, 10000, "target reached");
  }
};

TEST(Machine, SequenceFromIoFunctionsOnly) {
  Machine m;
  Rig& r = m.rig;
  using P = std::pair<bool, bool>;

  m.pulse(1);  // no software enable yet: the move's switch-on attempt faults
  EXPECT_EQ(r.sw() & 0x4F, 0x08);
  EXPECT_EQ(r.R(0x603F), 0xFFF2);
  EXPECT_EQ(m.feedback(), P(false, false));

  m.set(k_enable, true);
  m.pulse(1);  // the move resets the fault and runs
  EXPECT_EQ(r.R(0x3511, 4), 1);
  EXPECT_EQ(m.feedback(), P(false, false));
  m.settle();
  EXPECT_NEAR(static_cast<double>(r.R(0x6064)), k_a, 10);
  EXPECT_EQ(m.feedback(), P(true, false));

  m.pulse(2);
  m.settle();
  EXPECT_NEAR(static_cast<double>(r.R(0x6064)), k_b, 10);
  EXPECT_EQ(m.feedback(), P(false, true));

  m.set(std::int64_t{1} << 16, true);  // IN1: back towards A …
  r.step(30);
  m.set(std::int64_t{1} << 16, false);
  m.pulse(3);  // … stopped half way
  EXPECT_EQ(r.sw() & 0x6F, 0x07);
  r.until([&] { return r.R(0x606C) == 0; }, 2000, "standstill");
  const std::int64_t stop = r.R(0x6064);
  EXPECT_GT(stop, k_a + 100);
  EXPECT_LT(stop, k_b - 100);
  r.step(1000);
  EXPECT_NEAR(static_cast<double>(r.R(0x6064)), static_cast<double>(stop), 5);  // held, no move
  EXPECT_EQ(m.feedback(), P(false, false));

  m.pulse(2);  // leaves Quick Stop Active on its own
  m.settle();
  EXPECT_EQ(r.sw() & 0x6F, 0x27);
  EXPECT_EQ(m.feedback(), P(false, true));

  m.set(k_enable, false);  // enable lost: switched off without a fault, B is still held
  r.until([&] { return (r.sw() & 0x4F) == 0x40; }, 2000, "switch on disabled");
  r.step();
  EXPECT_EQ(m.feedback(), P(false, true));

  m.pulse(1);
  EXPECT_EQ(r.sw() & 0x4F, 0x08);
  EXPECT_EQ(m.feedback(), P(false, false));
  EXPECT_EQ(r.R(0x3511, 4), 2);  // the refused move did not count
}

}  // namespace
}  // namespace mcemu::iofunc::test
