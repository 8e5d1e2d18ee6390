// The whole drive bundle (device/device.hpp), the unit a fleet is made of (issue 26):
// - construction of one drive (dictionary, core, I/O functions, sessions, parts), per model family;
// - one 1 ms step of a drive moving in RefGo Back & Forth (every part of the step, not only the
//   core: the cost that grows with the number of moving drives);
// - one step of an idle drive, as the clock sees it (quiet_steps + skip).
// - one step of a FAULHABER drive running an MC BASIC program that never waits, at a given
//   faulhaber.basic_statements_per_ms: the cost of the budget's worst case (faulhaber.md §9.9,
//   docs/faulhaber.md "Execution model"); items/s = statements/s.
// Reports numbers only; nothing is asserted. Instruction counts: valgrind --tool=callgrind.
#include <benchmark/benchmark.h>
#include <malloc.h>

#include <memory>
#include <string>
#include <vector>

#include "device/scope.hpp"
#include "sim/steppable.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using mcemu::testing::DeviceFixture;
using mcemu::testing::DeviceOptions;

DeviceOptions quiet() {
  DeviceOptions o;
  o.keep_events = false;
  return o;
}

// Build and destroy a whole drive on a warm heap: what each fuzz input or a re-created drive pays.
// glibc gives the heap top back to the kernel once more than M_TRIM_THRESHOLD (128 KiB) is free at
// it, and a drive is ~200 KiB: without the threshold raised, every iteration here would pay ~50 page
// faults for re-growing the heap, a cost of this loop and not of building (a fleet builds its drives
// once, on fresh memory: bench/fleet.py's start-up column has that).
void BM_Construct(benchmark::State& state, const char* model) {
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
  for (auto _ : state) {
    DeviceFixture d(model, quiet());
    benchmark::DoNotOptimize(d.device().od().size());
  }
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
}
void BM_Construct_MC349(benchmark::State& state) { BM_Construct(state, "MC349"); }
void BM_Construct_FH_MC5005(benchmark::State& state) { BM_Construct(state, "FH_MC5005"); }

// A MovingCap in Back & Forth between 0 and 10 revolutions (RefGo, refgo.md §7.7), as bench/fleet.py.
// PWC enables the drive (a helper sequence that takes steps), then RR starts Back & Forth with a
// repeat way of 10 revolutions; throws when a line is refused (the benchmark would measure a drive
// that stands still).
void start_back_and_forth(DeviceFixture& d) {
  d.device().power_up_network();
  auto& refgo = d.refgo();
  const auto run = [&](const char* line) {
    const auto reply = refgo.execute(line);
    if (!reply || reply->find("error") != std::string::npos || reply->find('#') != std::string::npos) {
      throw std::runtime_error(std::string("RefGo refused ") + line + ": " + reply.value_or("(pending)"));
    }
  };
  run("PWC");
  d.step(50);
  for (const char* line : {"SP1000", "AC1000", "DE1000", "WT0", "RW655360", "RR"}) run(line);
  d.step(100);
  const auto at = d.core().raw_position_inc();
  d.step(10);
  if (d.core().raw_position_inc() == at) throw std::runtime_error("the drive does not move");
}

void BM_MovingStep_MC349(benchmark::State& state) {
  DeviceFixture d("MC349", quiet());
  start_back_and_forth(d);
  for (auto _ : state) d.step();
  benchmark::DoNotOptimize(d.core().raw_position_inc());
}

// N MovingCaps in Back & Forth, stepped in turn like a fleet's clock steps its drives: the time per
// drive step once the drives no longer share the caches (fleet.py measures the same through the
// server, with its sockets and script engines). Items = drive steps.
void BM_MovingFleet_MC349(benchmark::State& state) {
  std::vector<std::unique_ptr<DeviceFixture>> fleet;
  for (std::int64_t k = 0; k < state.range(0); ++k) {
    auto d = std::make_unique<DeviceFixture>("MC349", quiet());
    start_back_and_forth(*d);
    d->step(static_cast<std::uint64_t>(k));  // out of phase, as real drives are
    fleet.push_back(std::move(d));
  }
  std::vector<std::int64_t> before;
  for (auto& d : fleet) before.push_back(d->core().raw_position_inc());
  mcemu::sim::Fleet clock;  // stepped as the server's clock steps its fleet
  for (auto& d : fleet) clock.add(d->device().steps());
  for (auto _ : state) clock.step();
  state.SetItemsProcessed(state.iterations() * state.range(0));
  // The share of drives whose axis moved during the run: a fleet that stood still would measure
  // idle steps.
  std::size_t moved = 0;
  for (std::size_t k = 0; k < fleet.size(); ++k) moved += fleet[k]->core().raw_position_inc() != before[k];
  state.counters["moved"] = static_cast<double>(moved) / static_cast<double>(fleet.size());
}

// A FAULHABER drive moving in profile position between 0 and 40000 (a step of the whole bundle).
void BM_MovingStep_FH_MC5005(benchmark::State& state) {
  DeviceFixture d("FH_MC5005", quiet());
  d.device().power_up_network();
  d.step();  // not ready to switch on at t = 0 (faulhaber.md §7.1)
  d.W(0x6060, 0, 1);
  for (std::int64_t cw : {0x06, 0x0F}) {
    d.W(0x6040, 0, cw);
    d.step(20);
  }
  if (d.core().state() != mcemu::core::PdsState::operation_enabled) throw std::runtime_error("not enabled");
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
  state.counters["position"] = static_cast<double>(d.core().raw_position_inc());
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

// An FH_MC5005 bundle running `program` (slot 1) with budget state.range(0): one full step each.
void spin(benchmark::State& state, const char* program) {
  DeviceOptions o = quiet();
  o.config = {{"faulhaber", {{"basic_statements_per_ms", static_cast<std::uint64_t>(state.range(0))}}}};
  DeviceFixture d("FH_MC5005", o);
  d.device().power_up_network();
  (void)d.device().upload_program(1, program);
  (void)d.device().basic()->start(1);
  const auto& interp = d.device().basic()->interpreter();
  d.step();
  const auto before = interp.statements();
  for (auto _ : state) {
    d.device().steps().touch();  // always a full step, as a busy program makes it
    d.step();
  }
  if (!interp.running()) state.SkipWithError(interp.error().message.c_str());
  state.SetItemsProcessed(static_cast<std::int64_t>(interp.statements() - before));
}

// The tight loop of bench/basic_isolation.py: assignments only.
void BM_BasicSpin_Assign(benchmark::State& state) {
  spin(state, ":Spin\na = a + 1\nb = a\nc = b * 3 - a\nGOTO Spin\n");
}
// Every statement a SETOBJ that changes a value: a dictionary write with its hooks, a trace event
// (channel basic) and the master lint's write tap per statement.
void BM_BasicSpin_Setobj(benchmark::State& state) {
  spin(state, ":Spin\na = a + 1\nSETOBJ $607A.00 = a\nSETOBJ $6081.00 = a & $FFFF\nGOTO Spin\n");
}
// The heaviest statement there is: one line of a 4096-byte program with 220 GETOBJs in one
// expression (a dictionary read each; the loader bounds parentheses, not operands).
void BM_BasicSpin_GetobjLine(benchmark::State& state) {
  static const std::string text = [] {
    std::string line = "a = GETOBJ $6064.00";
    for (int i = 1; i < 220; ++i) line += " + GETOBJ $6064.00";
    return ":Spin\n" + line + "\nGOTO Spin\n";
  }();
  spin(state, text.c_str());
}

// The heap a moving MovingCap holds once its histories are full (issue 26: a moving fleet's memory
// over time): the 60 s scope ring and the trace ring (argument: its size, "trace": {"events": N}),
// after an hour of Back & Forth in drive time. Counters in KiB from malloc's own counts (mallinfo2:
// arena and mmapped blocks): the drive as built, and what the hour added.
void BM_MovingHourHeap_MC349(benchmark::State& state) {
  const auto heap = [] {
    const auto m = mallinfo2();
    return static_cast<double>(m.uordblks + m.hblkhd) / 1024.0;
  };
  for (auto _ : state) {
    const double h0 = heap();
    DeviceOptions o = quiet();
    o.config["trace"]["events"] = state.range(0);
    DeviceFixture d("MC349", std::move(o));
    start_back_and_forth(d);
    const double h1 = heap();
    d.step(3'600'000);
    state.counters["built_KiB"] = h1 - h0;
    state.counters["hour_KiB"] = heap() - h1;
    state.counters["trace_events"] = static_cast<double>(d.device().trace().size());
  }
}

// A full scope window of a moving drive read back: GET /api/v1/scope without sinceMs (arg 0), and
// the newest 100 ms a WebSocket scope period takes (arg 1). The ring keeps its runs as bytes, read
// from the oldest on.
void BM_ScopeRead(benchmark::State& state) {
  mcemu::device::Scope s;
  std::int32_t pos = 0;
  std::int32_t vel = 0;
  std::uint64_t t = 0;
  for (; t < 2 * mcemu::device::Scope::k_window_ms; t += 5) {
    vel = std::min(vel + 20, 4000);
    pos += vel / 200;
    s.add(t, mcemu::device::ScopeSample{pos, vel, 300 + static_cast<std::int32_t>(t % 7), 100000, 0x1237});
  }
  const std::uint64_t since = state.range(0) == 0 ? 0 : t - 100;
  for (auto _ : state) benchmark::DoNotOptimize(s.since_ms(since).samples.size());
  state.counters["encoded_bytes"] = static_cast<double>(s.encoded_bytes());
}

// One event into a full trace ring with a listener (the server's WebSocket hand-off), a drive
// event's text: the cost a moving drive pays per event.
void BM_TraceRecord(benchmark::State& state) {
  using mcemu::trace::Channel;
  using mcemu::trace::Dir;
  mcemu::trace::Ring ring{{[] { return std::uint64_t{1}; }, [] { return std::int64_t{0}; }}};
  std::size_t seen = 0;
  ring.set_listener([&seen](const mcemu::trace::Event& e) { seen += e.text.size(); });
  const std::string_view text = "StatuswordChanged 1127h -> 0127h";
  for (std::size_t i = 0; i < ring.capacity(); ++i) ring.record(Channel::drive, Dir::event, text);
  for (auto _ : state) ring.record(Channel::drive, Dir::event, text);
  benchmark::DoNotOptimize(seen);
}

}  // namespace

BENCHMARK(BM_BasicSpin_Assign)->Arg(20)->Arg(250);
BENCHMARK(BM_BasicSpin_Setobj)->Arg(20)->Arg(250);
BENCHMARK(BM_BasicSpin_GetobjLine)->Arg(20)->Arg(250);
BENCHMARK(BM_Construct_MC349)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Construct_FH_MC5005)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MovingStep_MC349);
BENCHMARK(BM_MovingStep_FH_MC5005);
BENCHMARK(BM_MovingFleet_MC349)->Arg(1)->Arg(100)->Arg(300)->Arg(1000);
BENCHMARK(BM_IdleMinute_MC349);
BENCHMARK(BM_ScopeRead)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MovingHourHeap_MC349)->Arg(10000)->Arg(1000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TraceRecord);
