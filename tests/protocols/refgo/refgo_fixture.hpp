// A drive for RefGo tests: preset, dictionary, powered core (booted to switch on disabled) and the
// interpreter, all in virtual time. step() advances the core and then the interpreter, as the
// server's clock does.
#pragma once

#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/refgo/interpreter.hpp"

namespace mcemu::refgo::test {

struct Drive {
  explicit Drive(const std::string& model = "MC349", const core::PlantConfig& plant = {})
      : preset(*model::find_preset(model)), od(preset), core(preset, od, plant), in(od, core) {
    core.power_on();
    step();
  }

  // Executes one line; a pending reply is returned as "<pending>".
  std::string run(std::string_view line) {
    auto r = in.execute(line);
    (void)core.drain_events();
    return r.value_or("<pending>");
  }
  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      core.step();
      in.on_step();
      (void)core.drain_events();
    }
  }
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

  model::ModelPreset preset;
  od::ObjectDictionary od;
  core::DriveCore core;
  Interpreter in;
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
