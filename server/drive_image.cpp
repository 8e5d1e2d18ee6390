#include "server/drive_image.hpp"

#include "persistence/state_document.hpp"

namespace mcemu::server {

using nlohmann::json;

namespace {

std::string hex_key(std::uint16_t i, std::uint8_t s) { return persistence::object_key(i, s); }

template <typename T>
T number_of(const json& v, const std::string& what) {
  if (!v.is_number()) throw UsageError("invalid value " + v.dump() + " for " + what + " (expected a number)");
  return v.get<T>();
}

std::uint32_t u32_of(const json& v, const std::string& what) {
  if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 0xFFFFFFFFLL) {
    throw UsageError("invalid value " + v.dump() + " for " + what + " (expected 0…4294967295)");
  }
  return static_cast<std::uint32_t>(v.get<std::int64_t>());
}

std::string string_of(const json& v, const std::string& what) {
  if (!v.is_string()) throw UsageError("invalid value " + v.dump() + " for " + what + " (expected a string)");
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
      throw UsageError("config: unknown key \"model_overrides." + key + "\"");
    }
  }
}

std::pair<std::int64_t, std::int64_t> pair_of(const json& v, const std::string& what) {
  if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer() ||
      v[0].get<std::int64_t>() >= v[1].get<std::int64_t>()) {
    throw UsageError("invalid value " + v.dump() + " for " + what + " (expected [min, max] in increments)");
  }
  return {v[0].get<std::int64_t>(), v[1].get<std::int64_t>()};
}

void apply_plant(model::ModelPreset& p, const json& o) {
  auto& pl = p.plant;
  std::optional<double> stroke_mm;
  bool stops_given = false;
  bool power_on_given = false;
  for (const auto& [key, v] : o.items()) {
    const std::string what = "config key \"plant." + key + "\"";
    const std::map<std::string, double*> doubles = {{"torque_peak", &pl.torque_peak},
                                                    {"torque_cont", &pl.torque_cont},
                                                    {"inertia_motor", &pl.inertia_motor},
                                                    {"inertia_load", &pl.inertia_load},
                                                    {"viscous", &pl.viscous},
                                                    {"coulomb", &pl.coulomb},
                                                    {"no_load_speed", &pl.no_load_speed},
                                                    {"velocity_bandwidth_hz", &pl.velocity_bandwidth_hz},
                                                    {"accel_feedforward", &pl.accel_feedforward},
                                                    {"moving_threshold", &pl.moving_threshold},
                                                    {"p_idle", &pl.p_idle_w},
                                                    {"p_cu", &pl.p_cu_w},
                                                    {"r_th", &pl.r_th_k_per_w},
                                                    {"tau_th", &pl.tau_th_s},
                                                    {"supply_nominal_v", &pl.supply_nominal_v},
                                                    {"uv_v", &pl.supply_uv_v},
                                                    {"ov_v", &pl.supply_ov_v}};
    if (auto it = doubles.find(key); it != doubles.end()) {
      *it->second = number_of<double>(v, what);
    } else if (key == "following_error_limit") {
      pl.following_error_limit_inc = number_of<std::int64_t>(v, what);
    } else if (key == "stops") {
      stops_given = true;
      if (v.is_null()) {
        pl.stops_inc.reset();
      } else {
        pl.stops_inc = pair_of(v, what);
      }
    } else if (key == "power_on_position") {
      power_on_given = true;
      pl.power_on_position_inc = number_of<std::int64_t>(v, what);
    } else if (key == "temperature_available" || key == "hw_enable_fitted" || key == "absolute_encoder") {
      if (!v.is_boolean()) throw UsageError("invalid value " + v.dump() + " for " + what + " (expected true/false)");
      (key == "temperature_available" ? pl.temperature_available
       : key == "hw_enable_fitted"    ? pl.hw_enable_fitted
                                      : pl.absolute_encoder) = v.get<bool>();
    } else if (key == "stroke_mm") {
      stroke_mm = number_of<double>(v, what);
    } else {
      // Further plant keys (e.g. position_switches, external_load) belong to the drive core's own
      // configuration and are validated there.
      continue;
    }
  }
  if (stroke_mm) {
    if (p.kind != model::Kind::linear || *stroke_mm < 1 || *stroke_mm > 650) {
      throw UsageError("invalid value for config key \"plant.stroke_mm\" (linear models only, 1…650)");
    }
    const auto len = static_cast<std::int64_t>(*stroke_mm * 1000.0);
    if (!stops_given) pl.stops_inc = std::pair<std::int64_t, std::int64_t>{0, len};
    if (!power_on_given) pl.power_on_position_inc = len / 2;
  }
  if (pl.hw_enable_fitted && pl.hw_enable_input == 0) {
    throw UsageError("config key \"plant.hw_enable_fitted\": on " + p.name +
                     " the HW enable option is a power pin, not an input (models.md §5)");
  }
  if (pl.torque_peak <= 0 || pl.inertia_motor + pl.inertia_load <= 0) {
    throw UsageError("config section \"plant\": torque_peak and the inertia must be positive");
  }
}

}  // namespace

model::ModelPreset make_preset(const Settings& settings) {
  auto p = model::find_preset(settings.model);
  if (!p) throw UsageError("unknown model '" + settings.model + "'");
  if (settings.config.contains("model_overrides")) apply_overrides(*p, settings.config["model_overrides"]);
  if (settings.config.contains("plant")) apply_plant(*p, settings.config["plant"]);
  return *p;
}

void apply_config_objects(od::ObjectDictionary& od, const json& config) {
  if (!config.contains("objects")) return;
  std::vector<od::StoredValue> values;
  for (const auto& [key, v] : config["objects"].items()) {
    const auto k = persistence::parse_object_key(key);
    if (!k) throw UsageError("config: object key \"" + key + "\" is not IIII.SS (hex)");
    if (!od.info(k->first, k->second)) throw UsageError("config: object " + key + " does not exist on this model");
    if (v.is_number_integer()) {
      values.push_back({k->first, k->second, od::Value{v.get<std::int64_t>()}});
    } else if (v.is_string()) {
      values.push_back({k->first, k->second, od::Value{v.get<std::string>()}});
    } else {
      throw UsageError("config: invalid value " + v.dump() + " for object " + key);
    }
  }
  const auto issues = od.load_values(values);
  if (!issues.empty()) {
    const auto& i = issues.front();
    char code[16];
    std::snprintf(code, sizeof code, "%08X", od::to_u32(i.code));
    throw UsageError("config: invalid value for object " + hex_key(i.index, i.sub) + " (abort code 0x" + code + ": " +
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
    entries.push_back(json{{"index", e.index},
                           {"sub", e.sub},
                           {"name", e.name},
                           {"type", od::to_string(e.type)},
                           {"access", od::to_string(e.access)},
                           {"pdo", od::to_string(e.pdo)},
                           {"class", od::to_string(e.cls)},
                           {"value", value}});
  });
  return json{{"model", model}, {"entries", entries}};
}

}  // namespace mcemu::server
