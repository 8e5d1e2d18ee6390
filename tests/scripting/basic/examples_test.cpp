// AN165's Examples A and B (faulhaber.md §10) as fixture files (the seed's texts with only the OCR
// artefacts removed): both load, and both run against a toy drive (harness.hpp FakeDrive) with the
// write sequences §10 asks for. The full acceptance runs against the real FAULHABER drive over the
// binary protocol are integration tests of the server; these check the interpreter's part, and
// that the same program and inputs give the same writes in the same steps (determinism).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/scripting/basic/harness.hpp"

namespace mcemu::basic {
namespace {

using test::FakeDrive;
using test::Rig;

std::string fixture(const char* name) {
  std::ifstream in(std::string(MCEMU_BASIC_FIXTURES) + "/" + name, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::pair<std::uint16_t, std::int64_t>> writes(const Rig& rig, std::size_t from = 0) {
  std::vector<std::pair<std::uint16_t, std::int64_t>> out;
  const auto w = rig.of_kind(EventKind::setobj);
  for (std::size_t i = from; i < w.size(); ++i) out.emplace_back(w[i].index, w[i].value);
  return out;
}

TEST(BasicExamples, BothFixturesLoadWithoutError) {
  for (const char* name : {"example_a.bas", "example_b.bas"}) {
    const std::string text = fixture(name);
    ASSERT_GT(text.size(), 1000U) << name;
    EXPECT_LE(text.size(), k_max_program_bytes) << name;
    auto r = load(text);
    const auto* e = std::get_if<LoadError>(&r);
    EXPECT_EQ(e, nullptr) << name << " line " << (e ? e->line : 0) << ": " << (e ? e->message : "");
  }
}

TEST(BasicExamples, ExampleBWritesItsProfileCycle) {
  Rig rig;
  FakeDrive drive(rig.od);
  rig.start(fixture("example_b.bas"));
  for (int ms = 0; ms < 10000 && rig.interp->running(); ++ms) {
    drive.step();
    rig.step();
  }
  ASSERT_TRUE(rig.interp->running()) << rig.interp->error().message;
  using W = std::vector<std::pair<std::uint16_t, std::int64_t>>;
  const W init{{0x6060, 1}, {0x2310, 0}, {0x2310, 0}, {0x6040, 0}, {0x6040, 0x06}, {0x6040, 0x0F}};
  const W cycle{{0x607A, 0},    {0x6068, 500},  {0x6040, 0x1F},  {0x6040, 0x0F}, {0x607A, 40000}, {0x6068, 20},
                {0x6040, 0x1F}, {0x6040, 0x0F}, {0x607A, 45000}, {0x6068, 100},  {0x6040, 0x1F},  {0x6040, 0x0F}};
  const W all = writes(rig);
  ASSERT_GE(all.size(), init.size() + 3 * cycle.size());
  EXPECT_EQ(W(all.begin(), all.begin() + 6), init);
  for (std::size_t c = 0; c < 3; ++c) {
    const auto from = all.begin() + static_cast<std::ptrdiff_t>(6 + c * cycle.size());
    EXPECT_EQ(W(from, from + static_cast<std::ptrdiff_t>(cycle.size())), cycle) << "cycle " << c;
  }
  EXPECT_EQ(rig.var('y'), 2);
}

TEST(BasicExamples, ExampleBIsDeterministic) {
  auto run = [] {
    Rig rig;
    FakeDrive drive(rig.od);
    rig.start(fixture("example_b.bas"));
    for (int ms = 0; ms < 5000; ++ms) {
      drive.step();
      rig.step();
    }
    std::vector<std::string> log;
    for (const auto& e : rig.events) log.push_back(std::to_string(e.time_ms) + " " + describe(e));
    return log;
  };
  const auto first = run();
  EXPECT_GT(first.size(), 30U);
  EXPECT_EQ(first, run());
}

TEST(BasicExamples, ExampleAHomesThenCyclesWithRampedAcceleration) {
  Rig rig;
  FakeDrive drive(rig.od);
  rig.start(fixture("example_a.bas"));
  auto run = [&](int ms) {
    for (int i = 0; i < ms && rig.interp->running(); ++i) {
      drive.step();
      rig.step();
    }
  };
  run(100);
  ASSERT_TRUE(rig.interp->running()) << rig.interp->error().message;
  using W = std::vector<std::pair<std::uint16_t, std::int64_t>>;
  const W init{{0x2310, 4},  {0x2310, 0},  {0x2310, 0}, {0x2310, 0},
               {0x6083, 10}, {0x6084, 10}, {0x6060, 6}, {0x6040, 0}};
  EXPECT_EQ(writes(rig), init);
  EXPECT_EQ(rig.var('y'), 1) << "disabled, waiting for DigIn1";
  EXPECT_EQ(rig.interp->quiet_steps(), k_never) << "waiting on an input costs nothing";

  const std::size_t before = writes(rig).size();
  rig.set(0x2311, 0x01, 0x01);  // DigIn1
  run(10);
  EXPECT_EQ(writes(rig, before), (W{{0x6040, 0x06}, {0x6040, 0x0F}, {0x6098, 17}, {0x6040, 0x1F}}));
  EXPECT_EQ(rig.var('y'), 3);
  run(100);  // homing completes after 50 ms
  EXPECT_GE(rig.var('z'), 2);

  run(60000);
  std::vector<std::int64_t> targets, acc, dec;
  for (const auto& [index, value] : writes(rig)) {
    if (index == 0x607A) targets.push_back(value);
    if (index == 0x6083) acc.push_back(value);
    if (index == 0x6084) dec.push_back(value);
  }
  ASSERT_GE(targets.size(), 10U);
  for (std::size_t i = 0; i < targets.size(); ++i) EXPECT_EQ(targets[i], i % 2 == 0 ? 10000 : -10000) << i;
  EXPECT_EQ(acc, dec);
  ASSERT_GE(acc.size(), 60U);
  // 10 (init), then 20, 30, …, 500, 490, …, 10, 20, …
  std::int64_t r = 10, q = 10;
  for (std::size_t i = 1; i < acc.size(); ++i) {
    r += q;
    if (r == 500 || r == 10) q = -q;
    ASSERT_EQ(acc[i], r) << "write " << i;
  }

  const std::size_t at_stop = writes(rig).size();
  rig.set(0x2311, 0x01, 0x02);  // DigIn1 low, DigIn2 high
  run(10);
  const W after = writes(rig, at_stop);
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(after.back(), (std::pair<std::uint16_t, std::int64_t>{0x6040, 0}));
  EXPECT_EQ(drive.state(), 0x40);
  run(2000);
  EXPECT_EQ(drive.state(), 0x40) << "stays disabled";
  EXPECT_EQ(rig.var('y'), 1);
}

}  // namespace
}  // namespace mcemu::basic
