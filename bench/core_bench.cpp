// 60 s of simulated motion of one drive (drive-core.md §2.3: goal < 100 ms CPU on a Release
// build). The drive is a bundle of the one test fixture (tests/support/device_fixture.hpp), of which
// only the drive core is stepped: the cost measured is the core's. Reports numbers only; nothing
// here is asserted.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <optional>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using mcemu::testing::DeviceFixture;

using mcemu::od::Origin;
using mcemu::od::Value;

void write(mcemu::od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::int64_t v) {
  od.write(index, sub, Value{v}, Origin::sdo);
}

mcemu::testing::DeviceOptions quiet() {
  mcemu::testing::DeviceOptions o;
  o.keep_events = false;  // the benchmark drains the core itself
  return o;
}

// Back-and-forth PP moves of 10 revolutions (or 100 mm) for 60 s of simulated time.
void run_minute(benchmark::State& state, const std::string& model) {
  std::uint64_t events = 0;
  std::optional<DeviceFixture> drive;
  for (auto _ : state) {
    state.PauseTiming();
    drive.reset();  // built and destroyed outside the timed part
    drive.emplace(model, quiet());
    auto& od = drive->od();
    auto& core = drive->core();
    const auto& preset = drive->preset();
    core.step();
    write(od, 0x6060, 0, 1);
    core.apply_mode_switch_now();
    write(od, 0x6040, 0, 0x06);
    write(od, 0x6040, 0, 0x07);
    write(od, 0x6040, 0, 0x0F);
    const std::int64_t stroke = preset.kind == mcemu::model::Kind::linear ? 50000 : 10 * 65536;
    state.ResumeTiming();
    for (int second = 0; second < 60; ++second) {
      write(od, 0x607A, 0, (second % 2 == 0) ? stroke : -stroke);
      write(od, 0x6040, 0, 0x6F);
      write(od, 0x6040, 0, 0x7F);
      core.step(1000);
      events += core.drain_events().size();
    }
    benchmark::DoNotOptimize(core.raw_position_inc());
  }
  state.counters["sim_s_per_iter"] = 60;
  state.counters["events"] = benchmark::Counter(static_cast<double>(events), benchmark::Counter::kAvgIterations);
}

void BM_Minute_MC349(benchmark::State& state) { run_minute(state, "MC349"); }
void BM_Minute_MCFLAT(benchmark::State& state) { run_minute(state, "MCFLAT"); }

// A drive idling in OE (the cost of one step with no motion).
void BM_IdleStep(benchmark::State& state) {
  DeviceFixture drive("MC349", quiet());
  auto& od = drive.od();
  auto& core = drive.core();
  core.step();
  write(od, 0x6040, 0, 0x06);
  write(od, 0x6040, 0, 0x07);
  write(od, 0x6040, 0, 0x0F);
  for (auto _ : state) core.step();
  benchmark::DoNotOptimize(core.raw_position_inc());
}

}  // namespace

BENCHMARK(BM_Minute_MC349)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Minute_MCFLAT)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_IdleStep);
