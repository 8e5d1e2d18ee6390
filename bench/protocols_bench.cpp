// Protocol cost without sockets: what one request costs in the pure layers behind TCP 15001 and
// 10001 (slcan-canopen.md §13: "≥ 2000 SDO requests/s per connection is a benchmark goal";
// refgo.md: polling clients send TP/OR in a loop). Reports numbers only; nothing is asserted.
#include <benchmark/benchmark.h>

#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/canopen/node.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/slcan/codec.hpp"

namespace {

using namespace std::chrono_literals;
using mcemu::can::Frame;

Frame sdo_request(std::uint8_t cs, std::uint16_t index, std::uint8_t sub) {
  Frame f;
  f.id = 0x600 + 50;
  f.dlc = 8;
  f.data = {cs, static_cast<std::uint8_t>(index & 0xFF), static_cast<std::uint8_t>(index >> 8), sub, 0, 0, 0, 0};
  return f;
}

struct Canopen {
  Canopen() : preset(*mcemu::model::find_preset("MC349")), od(preset), node(od, {}) {
    node.power_on(0ms);
    node.advance(10ms);
  }
  mcemu::model::ModelPreset preset;
  mcemu::od::ObjectDictionary od;
  mcemu::canopen::Node node;
};

// One expedited SDO upload of 6041h: request frame in, response frame out.
void BM_SdoExpeditedUpload(benchmark::State& state) {
  Canopen c;
  const Frame req = sdo_request(0x40, 0x6041, 0);
  for (auto _ : state) benchmark::DoNotOptimize(c.node.on_frame(req, 10ms));
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
    for (const auto& f : c.node.on_frame(cmd.frame, 10ms)) out += mcemu::slcan::encode_frame(f);
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
    benchmark::DoNotOptimize(c.node.on_frame(init, 10ms));
    benchmark::DoNotOptimize(c.node.on_frame(seg0, 10ms));
    benchmark::DoNotOptimize(c.node.on_frame(seg1, 10ms));
  }
  state.SetItemsProcessed(state.iterations());
}

struct Refgo {
  Refgo() : preset(*mcemu::model::find_preset("MC349")), od(preset), core(preset, od), interpreter(od, core) {
    core.power_on();
    core.step();
  }
  mcemu::model::ModelPreset preset;
  mcemu::od::ObjectDictionary od;
  mcemu::core::DriveCore core;
  mcemu::refgo::Interpreter interpreter;
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
BENCHMARK(BM_RefgoTP);
BENCHMARK(BM_RefgoORHex);
BENCHMARK(BM_RefgoOW);
