// Fuzz target: MC BASIC program text (faulhaber.md §9) → load → run. Input: byte 0 = statements per
// step (1 + b % 24) and bit 7 = idle detection off; byte 1 = seed of the outside changes (device
// status word 0x2324.01, the inputs 0x2311.01, a master write to a variable) at up to eight drive
// times; the rest is the program text.
// Oracles: the loader never crashes and reports a line inside the text (0 = its size); a loaded
// program runs 300 steps on a small dictionary without crashing, never runs more than N statements
// in a step, stops only in a state with a reason; and a twin that skips every quiet stretch
// (quiet_steps()/skip()) ends with exactly the events, variables, line and counters of the one
// stepped every millisecond.
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "scripting/basic/interpreter.hpp"
#include "scripting/basic/lexer.hpp"
#include "scripting/basic/loader.hpp"

using namespace mcemu;

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

od::EntryInfo entry(std::uint16_t index, std::uint8_t sub, od::DataType type, od::Access access) {
  od::EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.type = type;
  e.access = access;
  e.factory = std::int64_t{0};
  return e;
}

std::vector<od::EntryInfo> entries() {
  using od::Access;
  using od::DataType;
  std::vector<od::EntryInfo> v{
      entry(0x1008, 0, DataType::visible_string, Access::const_), entry(0x2310, 0x01, DataType::unsigned8, Access::rw),
      entry(0x2310, 0x03, DataType::integer16, Access::rw),       entry(0x2311, 0x01, DataType::unsigned16, Access::ro),
      entry(0x2324, 0x01, DataType::unsigned32, Access::ro),      entry(0x2400, 0x05, DataType::boolean, Access::rw),
      entry(0x3005, 0x00, DataType::unsigned8, Access::ro),       entry(0x6040, 0, DataType::unsigned16, Access::rw),
      entry(0x6041, 0, DataType::unsigned16, Access::ro),         entry(0x6060, 0, DataType::integer8, Access::rw),
      entry(0x607A, 0, DataType::integer32, Access::rw),          entry(0x6083, 0, DataType::unsigned32, Access::rw),
  };
  v[0].factory = std::string("MC");
  auto limited = entry(0x2310, 0x04, DataType::unsigned8, Access::rw);
  limited.limits = od::Range{0, 8};
  v.push_back(limited);
  for (std::uint8_t s = 1; s <= 26; ++s) v.push_back(entry(0x3005, s, DataType::integer32, Access::rw));
  return v;
}

struct Change {
  std::uint64_t at = 0;
  std::uint8_t what = 0;
  std::uint32_t value = 0;
};

struct Rig {
  Rig(const basic::Program& p, basic::Settings s) : od(entries()) {
    interp = std::make_unique<basic::Interpreter>(od, store, std::move(s), [this](const basic::Event& e) {
      log.push_back(std::to_string(e.time_ms) + " " + basic::describe(e));
    });
    interp->start(p, 1);
  }
  void apply(const Change& c) {
    switch (c.what % 3) {
      case 0: od.set(od.handle(0x2324, 1), od::Value{std::int64_t{c.value}}); break;
      case 1: od.set(od.handle(0x2311, 1), od::Value{std::int64_t{c.value & 0xFFFF}}); break;
      default:
        (void)od.write(0x3005, static_cast<std::uint8_t>(1 + c.value % 26),
                       od::Value{std::int64_t{static_cast<std::int32_t>(c.value)}}, od::Origin::sdo);
    }
  }
  od::ObjectDictionary od;
  basic::MemoryVariables store;
  std::unique_ptr<basic::Interpreter> interp;
  std::vector<std::string> log;
};

constexpr std::uint64_t k_steps = 300;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::uint32_t per_ms = 1 + data[0] % 24;
  const bool idle = (data[0] & 0x80) == 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 2), size - 2);

  auto loaded = basic::load(text);
  if (const auto* e = std::get_if<basic::LoadError>(&loaded)) {
    if (e->message.empty()) fail("a load error without a reason");
    const auto lines = basic::split_lines(text).size();
    if (e->line == 0 ? text.size() <= basic::k_max_program_bytes : e->line > lines) {
      fail("load error line " + std::to_string(e->line) + " outside the text (" + std::to_string(lines) + " lines)");
    }
    return 0;
  }
  const auto& program = std::get<basic::Program>(loaded);

  // up to eight outside changes at drive times derived from byte 1
  std::vector<Change> changes;
  std::uint32_t x = 0x9E3779B9U * (data[1] + 1U);
  for (int i = 0; i < 8 && (data[1] >> (i % 8) & 1); ++i) {
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    changes.push_back(Change{1 + (x % k_steps), static_cast<std::uint8_t>(x >> 8), x});
  }
  auto apply_due = [&](Rig& r, std::uint64_t t) {
    for (const auto& c : changes) {
      if (c.at == t) r.apply(c);
    }
  };

  basic::Settings settings;
  settings.statements_per_ms = per_ms;
  settings.idle_detection = idle;

  // the one stepped every millisecond
  Rig full(program, settings);
  for (std::uint64_t t = 1; t <= k_steps; ++t) {
    apply_due(full, t);
    const auto before = full.interp->statements();
    full.interp->step(t);
    if (full.interp->statements() - before > per_ms) fail("more statements in a step than the budget");
    const auto st = full.interp->state();
    if (st == basic::RunState::error && full.interp->error().message.empty()) fail("an error without a reason");
    if (st == basic::RunState::idle || st == basic::RunState::stopped) fail("a run ended in a state it cannot reach");
  }

  // the twin that skips quiet stretches up to the next outside change
  Rig twin(program, settings);
  std::uint64_t t = 0;
  while (t < k_steps) {
    if (twin.interp->quiet_steps() == basic::k_never) {
      std::uint64_t next = k_steps + 1;
      for (const auto& c : changes) {
        if (c.at > t && c.at < next) next = c.at;
      }
      const std::uint64_t n = next - 1 - t;
      if (n > 0) {
        twin.interp->skip(n);
        t += n;
        continue;
      }
    }
    ++t;
    apply_due(twin, t);
    twin.interp->step(t);
  }
  if (twin.log != full.log) fail("the skipping twin's events differ");
  if (twin.interp->state() != full.interp->state()) fail("the skipping twin's state differs");
  if (twin.interp->line() != full.interp->line()) fail("the skipping twin's line differs");
  if (twin.interp->statements() != full.interp->statements()) fail("the skipping twin's statement count differs");
  for (std::uint8_t s = 1; s <= 26; ++s) {
    if (twin.od.number(0x3005, s) != full.od.number(0x3005, s)) fail("the skipping twin's variables differ");
  }
  return 0;
}
