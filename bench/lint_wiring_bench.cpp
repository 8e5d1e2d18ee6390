// The master lint's wiring cost (issue 27 "Cost", docs/lint.md §8.5): one request through a real
// bundle's session as the server runs it — the RefGo `TP` line (wrapped session, the observer's
// request, the reply sink's reply) and an SDO upload of 6041h over SLCAN (wrapped session, the
// bus observer's frame classification and answer) — with the lint off (argument 0) and on with
// every rule at its default severity (1). The drive advances 1 ms every 20 requests, as at 20 000
// requests per second. CPU time per request; the difference is what the lint adds to the path that
// bench/echo_ratio measures through the sockets.
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>
#include <string>

#include "protocols/refgo/session.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using namespace mcemu;

nlohmann::json config_for(bool lint) { return {{"lint", {{"mode", lint ? "warn" : "off"}}}}; }

void BM_RefgoTp(benchmark::State& state) {
  const bool lint = state.range(0) != 0;
  testing::DeviceFixture d("MC349", config_for(lint));
  d.step(10);
  auto& hub = d.device().lint();
  auto inner = std::make_unique<refgo::Session>(d.refgo());
  auto* session = inner.get();
  auto wrapped = hub.wrap(std::move(inner), 7);
  std::string out;
  // as server/drive_listeners.cpp wires it
  session->set_reply_sink([&](std::string reply) {
    if (hub.active()) hub.reply(lint::Link::refgo, 7, lint::ReplyKind::response);
    out += reply;
  });
  refgo::Session::Observer observer;
  observer.received = [&](const line::Line& l) {
    if (hub.active()) hub.request(lint::Link::refgo, 7, l.overlong || d.refgo().attachment().route(l.text).execute);
  };
  session->set_observer(std::move(observer));
  int n = 0;
  for (auto _ : state) {
    wrapped->receive("TP\r");
    benchmark::DoNotOptimize(out);
    out.clear();
    if (++n % 20 == 0) d.step();
  }
  state.counters["findings"] = static_cast<double>(hub.engine().total(lint::Severity::info));
}
BENCHMARK(BM_RefgoTp)->Arg(0)->Arg(1)->ArgName("lint");

void BM_SdoUpload(benchmark::State& state) {
  const bool lint = state.range(0) != 0;
  testing::DeviceFixture d("MC349", config_for(lint));
  d.device().power_up_network();
  auto& hub = d.device().lint();
  auto s = hub.wrap(d.device().canopen()->make_session(), 7);
  int n = 0;
  for (auto _ : state) {
    s->receive("t63284041600000000000\r");
    benchmark::DoNotOptimize(s->take_output());
    if (++n % 20 == 0) d.step();
  }
  state.counters["findings"] = static_cast<double>(hub.engine().total(lint::Severity::warn));
}
BENCHMARK(BM_SdoUpload)->Arg(0)->Arg(1)->ArgName("lint");

}  // namespace
