#include "device/runtime_settings.hpp"

#include <algorithm>
#include <array>
#include <string_view>

namespace mcemu::device {

using nlohmann::json;

namespace {

enum class Kind : std::uint8_t { boolean, mib };

struct Key {
  std::string_view name;
  Kind kind;
  bool RuntimeSettings::*flag;  // for booleans
};

constexpr std::array<Key, 4> k_keys{{
    {"udpEmulatorNotes", Kind::boolean, &RuntimeSettings::udp_emulator_notes},
    {"scriptStrict", Kind::boolean, &RuntimeSettings::script_strict},
    {"scriptMemoryMiB", Kind::mib, nullptr},
    {"traceScriptCalls", Kind::boolean, &RuntimeSettings::trace_script_calls},
}};

}  // namespace

json settings_json(const RuntimeSettings& s) {
  return json{{"udpEmulatorNotes", s.udp_emulator_notes},
              {"scriptStrict", s.script_strict},
              {"scriptMemoryMiB", s.script_memory_mib},
              {"traceScriptCalls", s.trace_script_calls}};
}

std::optional<std::string> apply_settings(RuntimeSettings& s, const json& changes) {
  if (!changes.is_object()) return "settings must be a JSON object";
  RuntimeSettings next = s;
  for (const auto& item : changes.items()) {
    const std::string& name = item.key();  // not structured bindings: clang 14 cannot capture those
    const json& value = item.value();
    const auto key = std::find_if(k_keys.begin(), k_keys.end(), [&](const Key& k) { return k.name == name; });
    if (key == k_keys.end()) return "unknown setting \"" + name + "\"";
    if (key->kind == Kind::boolean) {
      if (!value.is_boolean()) return "setting \"" + name + "\" must be true or false";
      next.*(key->flag) = value.get<bool>();
    } else {
      if (!value.is_number_integer() || value.get<std::int64_t>() < 0 ||
          value.get<std::int64_t>() > RuntimeSettings::k_max_script_memory_mib) {
        return "setting \"" + name + "\" must be an integer number of MiB (0 … " +
               std::to_string(RuntimeSettings::k_max_script_memory_mib) + ")";
      }
      next.script_memory_mib = std::max(value.get<std::int64_t>(), RuntimeSettings::k_min_script_memory_mib);
    }
  }
  s = next;
  return std::nullopt;
}

std::optional<std::string> relaxation(const RuntimeSettings& start, const RuntimeSettings& next) {
  if (!next.script_strict && start.script_strict) {
    return "scriptStrict false lifts the MicroPython checks of scripts: it can only be set at start, in the "
           "\"settings\" section of the config file (docs/security.md)";
  }
  const std::int64_t ceiling = std::max(RuntimeSettings::k_default_script_memory_mib, start.script_memory_mib);
  if (next.script_memory_mib > ceiling) {
    return "scriptMemoryMiB above " + std::to_string(ceiling) +
           " can only be set at start, in the \"settings\" section of the config file (docs/security.md)";
  }
  return std::nullopt;
}

}  // namespace mcemu::device
