// The bundle's own configuration checks (device/device.cpp): the "faulhaber" keys the bundle reads
// itself — the MC BASIC budget, whose upper bound keeps one drive step cheap (docs/faulhaber.md
// "Execution model"). The factory image the bundle makes when it is first asked for.
#include "device/device.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "device/config_error.hpp"
#include "persistence/state_document.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::device {
namespace {

using mcemu::testing::DeviceFixture;
using nlohmann::json;

json budget(json value) { return json{{"faulhaber", {{"basic_statements_per_ms", std::move(value)}}}}; }

TEST(BasicBudget, AcceptsOneToTheMaximum) {
  for (const std::uint64_t n : {std::uint64_t{1}, std::uint64_t{20}, std::uint64_t{basic::k_max_statements_per_ms}}) {
    DeviceFixture d("FH_MC5005", budget(n));
    EXPECT_EQ(d.device().basic()->interpreter().settings().statements_per_ms, n);
  }
  EXPECT_EQ(basic::k_max_statements_per_ms, 250u);
}

TEST(BasicBudget, RefusesZeroAboveTheMaximumAndNonIntegers) {
  for (const json& bad : {json(0u), json(251u), json(1000u), json(100000u), json(-5), json(20.5), json("20")}) {
    try {
      DeviceFixture d("FH_MC5005", budget(bad));
      ADD_FAILURE() << bad.dump() << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()), "config: \"faulhaber.basic_statements_per_ms\" must be an integer 1 … 250")
          << bad.dump();
    }
  }
}

// "trace": {"events": N} sizes the drive's trace ring (docs/fleet.md "What a drive costs").
TEST(TraceEvents, SizeTheRing) {
  for (const std::size_t n : {std::size_t{1}, std::size_t{300}, k_max_trace_events}) {
    DeviceFixture d("MC349", json{{"trace", {{"events", n}}}});
    EXPECT_EQ(d.device().trace().capacity(), n);
  }
  EXPECT_EQ(DeviceFixture("MC349").device().trace().capacity(), trace::Ring::k_default_capacity);
  DeviceFixture d("FH_MC5005", json{{"trace", {{"events", 300}}}});
  for (int i = 0; i < 1000; ++i) d.device().trace().record(trace::Channel::api, trace::Dir::event, "x");
  EXPECT_EQ(d.device().trace().size(), 300u) << "the newest 300 events stay";
}

TEST(TraceEvents, RefusesWhatIsNotACount) {
  const std::string range = "config: \"trace.events\" must be an integer 1 … 1000000";
  for (const auto& [config, message] : std::vector<std::pair<json, std::string>>{
           {json{{"trace", 5}}, "config: \"trace\" must be an object"},
           {json{{"trace", {{"events", 0}}}}, range},
           {json{{"trace", {{"events", -3}}}}, range},
           {json{{"trace", {{"events", 1000001}}}}, range},
           {json{{"trace", {{"events", 50.5}}}}, range},
           {json{{"trace", {{"events", "100"}}}}, range},
           {json{{"trace", {{"size", 100}}}}, "config: unknown key \"trace.size\""}}) {
    try {
      DeviceFixture d("MC349", config);
      ADD_FAILURE() << config.dump() << " was accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(std::string(e.what()), message) << config.dump();
    }
  }
}

// persistence.md §5 steps 1–3: preset → dictionary → --config objects. The image is made when a
// restore, a motor store or a factory value first asks for it, long after the state file was loaded,
// --ip overlaid and RAM written: none of those may reach it.
TEST(FactoryImage, IsPresetAndConfigObjectsNotStateFileIpOrRam) {
  mcemu::testing::MemoryStorage storage;
  device::Setup setup;
  setup.model = "MC349";
  setup.config = json{{"objects", {{"6083.00", 2000}}}};
  setup.explicit_ip = std::array<std::uint8_t, 4>{10, 0, 0, 7};
  device::Environment env;
  env.storage = &storage;
  env.load_state = [](od::ObjectDictionary& od, const std::string&) -> std::optional<persistence::Image> {
    const std::vector<od::StoredValue> stored = {{0x6083, 0, od::Value{std::int64_t{4444}}},
                                                 {0x6084, 0, od::Value{std::int64_t{3333}}}};
    od.load_values(stored);
    return persistence::snapshot(od);
  };
  Device dev(std::move(setup), std::move(env));
  ASSERT_EQ(dev.od().number(0x6083, 0), 4444);
  ASSERT_EQ(dev.od().number(0x5007, 1), 10);
  ASSERT_EQ(dev.od().write(0x6084, 0, od::Value{std::int64_t{5555}}, od::Origin::sdo), od::AbortCode::none);

  const od::ObjectDictionary factory_preset(dev.preset());
  EXPECT_EQ(dev.factory_value(0x6083, 0), od::Value{std::int64_t{2000}});
  EXPECT_EQ(dev.factory_value(0x6084, 0), od::Value{factory_preset.number(0x6084, 0)});
  EXPECT_EQ(dev.factory_value(0x5007, 1), od::Value{factory_preset.number(0x5007, 1)});
  const auto dict = dev.factory_dictionary();
  EXPECT_EQ(dict->number(0x6083, 0), 2000);
  EXPECT_EQ(dict->number(0x6084, 0), factory_preset.number(0x6084, 0));
  EXPECT_NE(factory_preset.number(0x6084, 0), 3333);
  EXPECT_NE(factory_preset.number(0x5007, 1), 10);
}

}  // namespace
}  // namespace mcemu::device
