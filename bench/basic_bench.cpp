// MC BASIC interpreter cost (issue 25: "statements per second of wall time under --clock manual;
// goal ≥ 10⁶/s for a tight loop of assignments"). The dictionary is a real model's (MC349, a few
// hundred entries, so the binary searches of every variable access are realistic) plus the
// FAULHABER entries the interpreter uses, with one change listener as the server has. Reports
// numbers only; items/s = statements/s.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "scripting/basic/interpreter.hpp"
#include "scripting/basic/loader.hpp"

namespace {

using namespace mcemu;

std::vector<od::EntryInfo> entries() {
  const od::ObjectDictionary model(*model::find_preset("MC349"));
  std::vector<od::EntryInfo> v;
  model.for_each([&](const od::EntryInfo& e, const od::Value&) {
    if (e.index != 0x3005 && e.index != 0x2324) v.push_back(e);
  });
  auto add = [&](std::uint16_t index, std::uint8_t sub, od::DataType t, od::Access a) {
    od::EntryInfo e;
    e.index = index;
    e.sub = sub;
    e.type = t;
    e.access = a;
    e.factory = std::int64_t{0};
    v.push_back(e);
  };
  add(0x2324, 1, od::DataType::unsigned32, od::Access::ro);
  add(0x3005, 0, od::DataType::unsigned8, od::Access::ro);
  for (std::uint8_t s = 1; s <= 26; ++s) add(0x3005, s, od::DataType::integer32, od::Access::rw);
  return v;
}

struct Bench {
  Bench(const char* text, std::uint32_t per_ms) : od(entries()) {
    od.on_change([this](const od::EntryInfo&, const od::Value&) { ++changes; });
    auto r = basic::load(text);
    program = std::get<basic::Program>(std::move(r));
    basic::Settings s;
    s.statements_per_ms = per_ms;
    s.idle_detection = false;  // measure the statements, not the skipping
    interp = std::make_unique<basic::Interpreter>(od, store, s);
    interp->start(program);
  }
  od::ObjectDictionary od;
  basic::MemoryVariables store;
  basic::Program program;
  std::unique_ptr<basic::Interpreter> interp;
  std::uint64_t changes = 0;
  std::uint64_t now = 0;
};

void run(benchmark::State& state, const char* text, std::uint32_t per_ms) {
  Bench b(text, per_ms);
  const auto before = b.interp->statements();
  for (auto _ : state) b.interp->step(++b.now);
  if (!b.interp->running()) state.SkipWithError(b.interp->error().message.c_str());
  state.SetItemsProcessed(static_cast<std::int64_t>(b.interp->statements() - before));
  benchmark::DoNotOptimize(b.changes);
}

const char* k_assignments = ":L\na = a + 1\nb = a\nc = b * 3 - a\nGOTO L\n";

// The goal's case: a tight loop of assignments, 20 statements per 1 ms drive step (the default).
void BM_AssignmentLoop_20PerStep(benchmark::State& state) { run(state, k_assignments, 20); }
// The same with a large budget: the statements alone, without the per-step overhead.
void BM_AssignmentLoop_1000PerStep(benchmark::State& state) { run(state, k_assignments, 1000); }

// A polling main loop in AN165's style: GETOBJ of the statusword and an input, masks, IF blocks.
void BM_PollingLoop_20PerStep(benchmark::State& state) {
  run(state,
      ":L\n"
      "a = GETOBJ $6041.00\n"
      "s = a & $6F\n"
      "IF(y = 0) THEN\n"
      "  IF(s = $40) THEN\n"
      "    y = 0\n"
      "  ENDIF\n"
      "ELSEIF(y = 1) THEN\n"
      "  y = 1\n"
      "ENDIF\n"
      "n = (a & $0400) > 0\n"
      "GOTO L\n",
      20);
}

// The same loop with an event handler registered (0x2324.01 read before every statement).
void BM_AssignmentLoopWithEvent_20PerStep(benchmark::State& state) {
  run(state, "EN_EVT $10000, H\n:L\na = a + 1\nb = a\nc = b * 3 - a\nGOTO L\n:H\nRET_EVT\n", 20);
}

// Loading (checking and compiling) AN165's Example A sized program.
void BM_LoadProgram(benchmark::State& state) {
  std::string text;
  while (text.size() < 3800) {
    text +=
        "IF(y = 2) THEN\n"
        "   IF((s & $6F) = $27) THEN\n"
        "      y = 3\n"
        "   ENDIF\n"
        "ELSEIF(y = 3) THEN\n"
        "   SETOBJ $6040.00 = $0F ' comment\n"
        "ENDIF\n";
  }
  for (auto _ : state) benchmark::DoNotOptimize(basic::load(text));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
}

}  // namespace

BENCHMARK(BM_AssignmentLoop_20PerStep);
BENCHMARK(BM_AssignmentLoop_1000PerStep);
BENCHMARK(BM_PollingLoop_20PerStep);
BENCHMARK(BM_AssignmentLoopWithEvent_20PerStep);
BENCHMARK(BM_LoadProgram);
