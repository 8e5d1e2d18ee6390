// The runtime settings of web.md §8.9: RAM only, back to their start values (defaults or the
// "settings" section of --config) at process start, never stored.
// PURE: validation and JSON conversion; the owner (the router) applies a change and tells the
// server through its settings hook.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace mcemu::device {

struct RuntimeSettings {
  static constexpr std::int64_t k_min_script_memory_mib = 32;
  static constexpr std::int64_t k_default_script_memory_mib = 256;
  static constexpr std::int64_t k_max_script_memory_mib = 1024 * 1024;  // 1 TiB: a sanity bound

  bool udp_emulator_notes = false;  // "mcemu:" notes on UDP (udp-debug.md §4.7)
  bool script_strict = true;        // MicroPython limits (scripting.md §9)
  std::int64_t script_memory_mib = k_default_script_memory_mib;
  bool trace_script_calls = false;

  bool operator==(const RuntimeSettings&) const = default;
};

nlohmann::json settings_json(const RuntimeSettings& s);

// Applies a subset {"udpEmulatorNotes": true, …} to `s`. All or nothing: on an unknown key or a
// wrong type the message names the key and `s` is unchanged. scriptMemoryMiB below 32 is taken as 32.
std::optional<std::string> apply_settings(RuntimeSettings& s, const nlohmann::json& changes);

// docs/security.md: what PUT /api/v1/settings may not do (403). Over HTTP the script settings may
// be tightened, never relaxed beyond the start values (the command line or the "settings" section
// of the config file): scriptStrict false while it started true, or a scriptMemoryMiB above both
// the default and its start value. The reason, or nullopt if `next` is allowed.
std::optional<std::string> relaxation(const RuntimeSettings& start, const RuntimeSettings& next);

}  // namespace mcemu::device
