#include "device/config_image.hpp"

#include <cstdio>

#include "persistence/state_document.hpp"
#include "protocols/faulhaber/config.hpp"

namespace mcemu::device {

using nlohmann::json;

namespace {

std::string hex_key(std::uint16_t i, std::uint8_t s) { return persistence::object_key(i, s); }

std::uint32_t u32_of(const json& v, const std::string& what) {
  if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 0xFFFFFFFFLL) {
    throw ConfigError("invalid value " + v.dump() + " for " + what + " (expected 0…4294967295)");
  }
  return static_cast<std::uint32_t>(v.get<std::int64_t>());
}

std::string string_of(const json& v, const std::string& what) {
  if (!v.is_string()) throw ConfigError("invalid value " + v.dump() + " for " + what + " (expected a string)");
  return v.get<std::string>();
}

void apply_overrides(model::ModelPreset& p, const json& o) {
  for (const auto& [key, v] : o.items()) {
    const std::string what = "config key \"model_overrides." + key + "\"";
    auto& id = p.identity;
    if (key == "device_name") {
      id.device_name = string_of(v, what);
    } else if (key == "software_version") {
      id.software_version = string_of(v, what);
    } else if (key == "hardware_version") {
      id.hardware_version = string_of(v, what);
    } else if (key == "display_name") {
      id.display_name = string_of(v, what);
    } else if (key == "short_name") {
      id.short_name = string_of(v, what);
    } else if (key == "serial") {
      id.serial = u32_of(v, what);
    } else if (key == "vendor_id") {
      id.vendor_id = u32_of(v, what);
    } else if (key == "product_code") {
      id.product_code = u32_of(v, what);
    } else if (key == "revision") {
      id.revision = u32_of(v, what);
    } else if (key == "encoder_inc") {
      p.encoder_inc = u32_of(v, what);
    } else {
      throw ConfigError("config: unknown key \"model_overrides." + key + "\"");
    }
  }
}

// The "faulhaber" section's dictionary keys (faulhaber.md §1, §4, §8): the device name 1008h, the
// serial 1018h.04, the factory node-id 0x2400.03 and the CRC switch of 0x2400.04. The protocol's and
// MC BASIC's own keys are validated here too, so a typo stops start-up on every model.
void apply_faulhaber(model::ModelPreset& p, const json& section) {
  if (!section.is_object()) throw ConfigError("config: \"faulhaber\" must be an object");
  faulhaber::FaulhaberConfig fh;
  try {
    fh = faulhaber::faulhaber_config_from_json(section);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(std::string("config: ") + e.what());
  }
  if (!p.is_faulhaber()) throw ConfigError("config: \"faulhaber\" applies to the FH_… models only, not " + p.name);
  if (const auto it = section.find("device_name"); it != section.end()) {
    const auto name = string_of(*it, "config key \"faulhaber.device_name\"");
    if (name.empty() || name.size() > 58)
      throw ConfigError("config: \"faulhaber.device_name\" must be 1 … 58 characters");
    p.identity.device_name = name;
  }
  if (const auto it = section.find("serial"); it != section.end()) {
    p.identity.serial = u32_of(*it, "config key \"faulhaber.serial\"");
  }
  p.factory_values[{0x2400, 0x03}] = fh.node_id;
  p.factory_values[{0x2400, 0x04}] = static_cast<std::int64_t>(faulhaber::factory_settings(fh));
}

}  // namespace

model::ModelPreset make_preset(const std::string& model, const nlohmann::json& config) {
  auto p = model::find_preset(model);
  if (!p) throw ConfigError("unknown model '" + model + "'");
  if (config.contains("model_overrides")) apply_overrides(*p, config["model_overrides"]);
  if (config.contains("faulhaber")) apply_faulhaber(*p, config["faulhaber"]);
  return *p;
}

void apply_config_objects(od::ObjectDictionary& od, const json& config) {
  if (!config.contains("objects")) return;
  std::vector<od::StoredValue> values;
  for (const auto& [key, v] : config["objects"].items()) {
    const auto k = persistence::parse_object_key(key);
    if (!k) throw ConfigError("config: object key \"" + key + "\" is not IIII.SS (hex)");
    if (!od.info(k->first, k->second)) throw ConfigError("config: object " + key + " does not exist on this model");
    if (v.is_number_integer()) {
      values.push_back({k->first, k->second, od::Value{v.get<std::int64_t>()}});
    } else if (v.is_string()) {
      values.push_back({k->first, k->second, od::Value{v.get<std::string>()}});
    } else {
      throw ConfigError("config: invalid value " + v.dump() + " for object " + key);
    }
  }
  const auto issues = od.load_values(values);
  if (!issues.empty()) {
    const auto& i = issues.front();
    char code[16];
    std::snprintf(code, sizeof code, "%08X", od::to_u32(i.code));
    throw ConfigError("config: invalid value for object " + hex_key(i.index, i.sub) + " (abort code 0x" + code + ": " +
                      std::string(od::description(i.code)) + ")");
  }
}

json dump_od(const od::ObjectDictionary& od, const std::string& model) {
  json entries = json::array();
  od.for_each([&](const od::EntryInfo& e, const od::Value&) {
    json value;
    auto r = od.read(e.index, e.sub);
    if (r) {
      if (std::holds_alternative<std::int64_t>(*r)) {
        value = std::get<std::int64_t>(*r);
      } else {
        value = std::get<std::string>(*r);
      }
    }
    json entry{{"index", e.index},
               {"sub", e.sub},
               {"name", e.name},
               {"type", od::to_string(e.type)},
               {"access", od::to_string(e.access)},
               {"pdo", od::to_string(e.pdo)},
               {"class", od::to_string(e.cls)},
               {"value", value}};
    if (e.limits) {  // object-dictionary.md §5 ranges (sets and structural rules are not listed)
      entry["min"] = e.limits->min;
      entry["max"] = e.limits->max;
    }
    entries.push_back(std::move(entry));
  });
  return json{{"model", model}, {"entries", entries}};
}

}  // namespace mcemu::device
