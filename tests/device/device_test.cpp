// The bundle's own configuration checks (device/device.cpp): the "faulhaber" keys the bundle reads
// itself — the MC BASIC budget, whose upper bound keeps one drive step cheap (docs/faulhaber.md
// "Execution model").
#include "device/device.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "device/config_error.hpp"
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

}  // namespace
}  // namespace mcemu::device
