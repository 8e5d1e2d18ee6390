// The whole drive bundle (device/device.hpp), the unit a fleet is made of (issue 26):
// - construction of one drive (dictionary, core, I/O functions, sessions, parts), per model family;
// - one 1 ms step of a drive moving in RefGo Back & Forth (every part of the step, not only the
//   core: the cost that grows with the number of moving drives);
// - one step of an idle drive, as the clock sees it (quiet_steps + skip).
// Reports numbers only; nothing is asserted. Instruction counts: valgrind --tool=callgrind.
#include <benchmark/benchmark.h>

#include <string>

#include "tests/support/device_fixture.hpp"

namespace {

using mcemu::testing::DeviceFixture;
using mcemu::testing::DeviceOptions;

DeviceOptions quiet() {
  DeviceOptions o;
  o.keep_events = false;
  return o;
}

void BM_Construct(benchmark::State& state, const char* model) {
  for (auto _ : state) {
    DeviceFixture d(model, quiet());
    benchmark::DoNotOptimize(d.device().od().size());
  }
}
void BM_Construct_MC349(benchmark::State& state) { BM_Construct(state, "MC349"); }
void BM_Construct_FH_MC5005(benchmark::State& state) { BM_Construct(state, "FH_MC5005"); }

// A MovingCap in Back & Forth between 0 and 10 revolutions (RefGo, refgo.md §7.7), as bench/fleet.py.
void BM_MovingStep_MC349(benchmark::State& state) {
  DeviceFixture d("MC349", quiet());
  d.device().power_up_network();
  auto& refgo = d.refgo();
  for (const char* line : {"EN", "SP1000", "AC1000", "DC1000", "WT0", "RW655360", "BF"}) (void)refgo.execute(line);
  d.step(100);
  for (auto _ : state) d.step();
  benchmark::DoNotOptimize(d.core().raw_position_inc());
}

// A FAULHABER drive moving in profile position between 0 and 40000 (a step of the whole bundle).
void BM_MovingStep_FH_MC5005(benchmark::State& state) {
  DeviceFixture d("FH_MC5005", quiet());
  d.device().power_up_network();
  d.W(0x6060, 0, 1);
  for (std::int64_t cw : {0x06, 0x0F}) d.W(0x6040, 0, cw);
  std::int64_t target = 40000;
  std::uint64_t n = 0;
  for (auto _ : state) {
    if (++n % 2000 == 1) {
      d.W(0x607A, 0, target);
      d.W(0x6040, 0, 0x1F);
      d.W(0x6040, 0, 0x0F);
      target = -target;
    }
    d.step();
  }
  benchmark::DoNotOptimize(d.core().raw_position_inc());
}

// An idle drive as the clock sees it: how long it may sleep, then a skip of a minute.
void BM_IdleMinute_MC349(benchmark::State& state) {
  DeviceFixture d("MC349", quiet());
  d.device().power_up_network();
  auto& steps = d.device().steps();
  for (auto _ : state) {
    const auto q = steps.quiet_steps();
    steps.skip(q < 60000 ? q : 60000);
    benchmark::DoNotOptimize(q);
  }
}

}  // namespace

BENCHMARK(BM_Construct_MC349)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Construct_FH_MC5005)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MovingStep_MC349);
BENCHMARK(BM_MovingStep_FH_MC5005);
BENCHMARK(BM_IdleMinute_MC349);
