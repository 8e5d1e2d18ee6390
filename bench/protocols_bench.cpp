// Protocol cost without sockets: what one request costs in the pure layers behind TCP 15001 and
// 10001 (slcan-canopen.md §13: "≥ 2000 SDO requests/s per connection is a benchmark goal";
// refgo.md: polling clients send TP/OR in a loop). Reports numbers only; nothing is asserted.
#include <benchmark/benchmark.h>

#include <string>

#include "protocols/canopen/node.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/slcan/codec.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using mcemu::can::Frame;

Frame sdo_request(std::uint8_t cs, std::uint16_t index, std::uint8_t sub) {
  Frame f;
  f.id = 0x600 + 50;
  f.dlc = 8;
  f.data = {cs, static_cast<std::uint8_t>(index & 0xFF), static_cast<std::uint8_t>(index >> 8), sub, 0, 0, 0, 0};
  return f;
}

// The CANopen node of a drive bundle (tests/support/device_fixture.hpp), booted as at the start of
// mcemu; requests arrive at the bus time of the boot-up.
struct Canopen {
  Canopen() : node(drive.device().canopen()->node()) {
    drive.device().power_up_network();
    now = drive.device().canopen()->now();
  }
  mcemu::testing::DeviceFixture drive;
  mcemu::canopen::Node& node;
  std::chrono::milliseconds now{0};
};

// One expedited SDO upload of 6041h: request frame in, response frame out.
void BM_SdoExpeditedUpload(benchmark::State& state) {
  Canopen c;
  const Frame req = sdo_request(0x40, 0x6041, 0);
  for (auto _ : state) benchmark::DoNotOptimize(c.node.on_frame(req, c.now));
  state.SetItemsProcessed(state.iterations());
}

// The same request as the SLCAN bytes a client sends and receives: parse, node, encode.
void BM_SdoUploadThroughSlcanText(benchmark::State& state) {
  Canopen c;
  const std::string line = "t63284041600000000000";
  for (auto _ : state) {
    const auto parsed = mcemu::slcan::parse_line(line);
    const auto& cmd = std::get<mcemu::slcan::Command>(parsed);
    std::string out;
    for (const auto& f : c.node.on_frame(cmd.frame, c.now)) out += mcemu::slcan::encode_frame(f);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}

// A segmented upload of 1008h (12 bytes: initiate + 2 segments).
void BM_SdoSegmentedUpload1008(benchmark::State& state) {
  Canopen c;
  const Frame init = sdo_request(0x40, 0x1008, 0);
  Frame seg0 = sdo_request(0x60, 0, 0);
  Frame seg1 = sdo_request(0x70, 0, 0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(c.node.on_frame(init, c.now));
    benchmark::DoNotOptimize(c.node.on_frame(seg0, c.now));
    benchmark::DoNotOptimize(c.node.on_frame(seg1, c.now));
  }
  state.SetItemsProcessed(state.iterations());
}

// The node's share of a moving drive's step in OPERATIONAL (slcan-canopen.md §9.4): advance() after
// every 1 ms step, with position actual 6064h (mapped in TPDO 3, RTR-only, so nothing is sent)
// changed by the drive in between, as the core does. Event-driven TPDOs 1–2 see no change.
void BM_NodeAdvanceOperational(benchmark::State& state) {
  Canopen c;
  mcemu::can::Frame start;
  start.id = 0;
  start.dlc = 2;
  start.data = {0x01, 0x00, 0, 0, 0, 0, 0, 0};
  benchmark::DoNotOptimize(c.node.on_frame(start, c.now));
  auto& od = c.drive.od();
  const auto position = od.handle(0x6064, 0);
  std::int64_t p = 0;
  for (auto _ : state) {
    (void)od.set(position, mcemu::od::Value{++p});
    c.now += std::chrono::milliseconds(1);
    benchmark::DoNotOptimize(c.node.advance(c.now));
  }
  state.SetItemsProcessed(state.iterations());
}

// The RefGo interpreter of a drive bundle, one step after power on.
struct Refgo {
  Refgo() : interpreter(drive.refgo()) { drive.step(); }
  mcemu::testing::DeviceFixture drive;
  mcemu::refgo::Interpreter& interpreter;
};

void refgo_line(benchmark::State& state, const char* line) {
  Refgo r;
  for (auto _ : state) benchmark::DoNotOptimize(r.interpreter.execute(line));
  state.SetItemsProcessed(state.iterations());
}

void BM_RefgoTP(benchmark::State& state) { refgo_line(state, "TP"); }
void BM_RefgoORHex(benchmark::State& state) { refgo_line(state, "OR6041,0,h"); }
void BM_RefgoOW(benchmark::State& state) { refgo_line(state, "OW6083,0,2000"); }

}  // namespace

BENCHMARK(BM_SdoExpeditedUpload);
BENCHMARK(BM_SdoUploadThroughSlcanText);
BENCHMARK(BM_SdoSegmentedUpload1008);
BENCHMARK(BM_NodeAdvanceOperational);
BENCHMARK(BM_RefgoTP);
BENCHMARK(BM_RefgoORHex);
BENCHMARK(BM_RefgoOW);
