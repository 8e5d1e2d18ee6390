// A drive for RefGo tests: a drive bundle built by the one fixture (tests/support/device_fixture.hpp),
// booted to switch on disabled, and its own RefGo interpreter, all in virtual time. step() is the
// bundle's step (the drive, then the parts: the interpreter's programs among them), as the server's
// clock runs it.
#pragma once

#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "tests/support/device_fixture.hpp"

namespace mcemu::refgo::test {

struct Drive {
  explicit Drive(const std::string& model = "MC349", const core::PlantConfig& plant = {})
      : fixture(model, options(plant)),
        preset(fixture.preset()),
        od(fixture.od()),
        core(fixture.core()),
        in(fixture.refgo()) {
    step();
  }

  // Executes one line, then the event hand-off as after a request; a pending reply is returned as
  // "<pending>".
  std::string run(std::string_view line) {
    auto r = in.execute(line);
    fixture.device().handle_events();
    return r.value_or("<pending>");
  }
  void step(std::uint64_t n = 1) { fixture.step(n); }
  // Steps until pred() holds; returns the steps taken, or max_ms + 1.
  template <typename Pred>
  std::uint64_t step_until(Pred pred, std::uint64_t max_ms) {
    for (std::uint64_t i = 1; i <= max_ms; ++i) {
      step();
      if (pred()) return i;
    }
    return max_ms + 1;
  }
  std::int64_t get(std::uint16_t index, std::uint8_t sub = 0) const { return od.number(index, sub); }
  void set(std::uint16_t index, std::uint8_t sub, std::int64_t v) {
    ASSERT_EQ(od.write(index, sub, od::Value{v}, od::Origin::internal), od::AbortCode::none);
  }
  std::uint16_t sw() const { return static_cast<std::uint16_t>(get(0x6041)); }
  bool reached() const { return (sw() & 0x0400) != 0; }
  // The answer line of a reply "<echo>\r\n<answer>\r\n>".
  static std::string answer_of(const std::string& reply) {
    const auto a = reply.find("\r\n");
    const auto b = reply.rfind("\r\n>");
    if (a == std::string::npos || b == std::string::npos || b <= a) return {};
    return reply.substr(a + 2, b - a - 2);
  }
  std::string tpsr() { return answer_of(run("TPSR")); }
  std::string ts() { return answer_of(run("TS")); }
  std::int64_t tp() { return std::stoll(answer_of(run("TP"))); }

  // Removes the persistence service's Store/Restore hooks, for tests that install their own.
  void release_store_hooks() { fixture.release_store_hooks(); }

  static mcemu::testing::DeviceOptions options(const core::PlantConfig& plant) {
    mcemu::testing::DeviceOptions o;
    o.plant = plant;
    o.keep_events = false;
    return o;
  }

  mcemu::testing::DeviceFixture fixture;
  const model::ModelPreset& preset;
  od::ObjectDictionary& od;
  core::DriveCore& core;
  Interpreter& in;
};

// "{TP}" in an expected reply stands for a signed decimal (refgo.md §14).
inline bool matches_vector(const std::string& got, const std::string& expected) {
  std::string pattern;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (expected.compare(i, 4, "{TP}") == 0) {
      pattern += "-?[0-9]+";
      i += 3;
      continue;
    }
    const char c = expected[i];
    if (std::string_view("\\^$.|?*+()[]{}").find(c) != std::string_view::npos) pattern += '\\';
    pattern += c;
  }
  return std::regex_match(got, std::regex(pattern));
}

}  // namespace mcemu::refgo::test
