// Master lint cost (issue 27 "Cost"): nanoseconds per observation with every rule on, for the
// streams a busy drive produces — RPDO/SDO controlword traffic, RefGo polling, SDO request/answer
// pairs — plus a stream that fires findings (rate-limited) and the mode-off path. Also the CANopen
// classification helper on a real MC349 dictionary. Reports numbers only; items/s = observations/s.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "lint/canopen_view.hpp"
#include "lint/engine.hpp"

namespace {

using namespace mcemu;
using namespace mcemu::lint;

Config every_rule_on() {
  Config c;
  for (auto& s : c.severity) s = Severity::warn;
  return c;
}

OdWrite cw_write(Ms t, std::uint16_t cw, std::uint16_t sw_after) {
  OdWrite w;
  w.time = t;
  w.conn = 1;
  w.origin = od::Origin::sdo;
  w.index = 0x6040;
  w.value = cw;
  w.statusword_after = sw_after;
  w.mode_after = 1;
  return w;
}

// A careful PP master: set-point edge, acknowledge seen, bit 4 back to 0 — no findings.
void BM_ControlwordWrites(benchmark::State& state) {
  Engine e(every_rule_on());
  const core::Event oe = core::StatuswordChanged{0x0040, 0x0027};
  e.observe(CoreEvent{0, oe});
  Ms t = 0;
  for (auto _ : state) {
    ++t;
    e.observe(cw_write(t, 0x001F, 0x1127));
    e.observe(cw_write(t, 0x000F, 0x0127));
  }
  if (e.recent().size() != 0) state.SkipWithError("unexpected findings");
  state.SetItemsProcessed(state.iterations() * 2);
}
BENCHMARK(BM_ControlwordWrites);

// RPDO3 (6040h, 607Ah) as the dictionary tap sees it: two writes per frame, plus the frame.
void BM_RpdoFrame(benchmark::State& state) {
  Engine e(every_rule_on());
  const core::Event oe = core::StatuswordChanged{0x0040, 0x0027};
  e.observe(CoreEvent{0, oe});
  e.observe(NmtChange{0, Nmt::pre_operational, Nmt::operational});
  e.observe(CanRequest{0, 1, CanKind::guarding, 0, 0, false, 0});
  Ms t = 0;
  for (auto _ : state) {
    ++t;
    e.observe(CanRequest{t, 1, CanKind::rpdo, 0, 3, true, 300});
    OdWrite target = cw_write(t, 0, 0x0027);
    target.index = 0x607A;
    target.value = static_cast<std::int64_t>(t);
    e.observe(target);
    e.observe(cw_write(t, (t & 1) ? 0x001F : 0x000F, 0x0027));
  }
  state.SetItemsProcessed(state.iterations() * 3);
}
BENCHMARK(BM_RpdoFrame);

// The SDO echo stream: request frame, the write it makes, the answer frame.
void BM_SdoWritePairs(benchmark::State& state) {
  Engine e(every_rule_on());
  e.observe(NmtChange{0, Nmt::initialising, Nmt::pre_operational});
  Ms t = 0;
  for (auto _ : state) {
    ++t;
    e.observe(CanRequest{t, 1, CanKind::sdo, 0x2B, 0, false, 0});
    OdWrite w = cw_write(t, 0, 0x0040);
    w.index = 0x6081;
    w.value = 1000;
    e.observe(w);
    e.observe(SdoAnswer{t, 0x60});
  }
  state.SetItemsProcessed(state.iterations() * 3);
}
BENCHMARK(BM_SdoWritePairs);

// The RefGo echo stream: one request and its reply per 5 ms, one connection of several.
void BM_RefgoRequestReply(benchmark::State& state) {
  Engine e(every_rule_on());
  Ms t = 0;
  for (auto _ : state) {
    t += 5;
    const Conn conn = 1 + (t / 5) % 8;
    e.observe(ProtocolRequest{t, Link::refgo, conn, t, true});
    e.observe(ProtocolReply{t, Link::refgo, conn, ReplyKind::response});
  }
  state.SetItemsProcessed(state.iterations() * 2);
}
BENCHMARK(BM_RefgoRequestReply);

// A sloppy master: every request races the previous reply; five findings per second are
// formatted, the rest counted as suppressed.
void BM_FindingsRateLimited(benchmark::State& state) {
  Engine e(every_rule_on());
  Ms t = 0;
  std::uint64_t n = 0;
  for (auto _ : state) {
    if (++n % 4 == 0) ++t;
    e.observe(ProtocolRequest{t, Link::refgo, 1, 0, true});
  }
  state.counters["reported"] = static_cast<double>(e.counts(RuleId::refgo_request_before_reply).reported);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FindingsRateLimited);

// Every occurrence reported (no rate limit): the cost of one finding, string and ring included.
void BM_FindingsUnlimited(benchmark::State& state) {
  Config c = every_rule_on();
  c.findings_per_second = 0;
  Engine e(c, [](const Finding& f) { benchmark::DoNotOptimize(f.detail.data()); });
  Ms t = 0;
  for (auto _ : state) e.observe(ProtocolRequest{++t, Link::refgo, 1, 0, true});
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FindingsUnlimited);

void BM_ModeOff(benchmark::State& state) {
  Config c = every_rule_on();
  c.mode = Mode::off;
  Engine e(c);
  Ms t = 0;
  for (auto _ : state) e.observe(cw_write(++t, 0x000F, 0x0027));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ModeOff);

// classify_can_frame on MC349: an SDO request (fixed identifiers, no dictionary access) and an
// RPDO (four COB-ID lookups, the mapping and the guarding objects).
void BM_ClassifySdo(benchmark::State& state) {
  const od::ObjectDictionary od(*model::find_preset("MC349"));
  const std::uint8_t data[8] = {0x40, 0x41, 0x60, 0, 0, 0, 0, 0};
  for (auto _ : state) benchmark::DoNotOptimize(classify_can_frame(od, 1, 1, 0x632, false, 8, data, 50));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClassifySdo);

void BM_ClassifyRpdo(benchmark::State& state) {
  const od::ObjectDictionary od(*model::find_preset("MC349"));
  const std::uint8_t data[8] = {0x0F, 0, 0, 0, 0, 0, 0, 0};
  for (auto _ : state) benchmark::DoNotOptimize(classify_can_frame(od, 1, 1, 0x432, false, 6, data, 50));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClassifyRpdo);

}  // namespace
