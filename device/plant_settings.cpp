#include "device/plant_settings.hpp"

#include <functional>
#include <map>
#include <string>

#include "device/config_error.hpp"

namespace mcemu::device {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& key, const std::string& expected) {
  throw ConfigError("invalid value for " + key + " in --config (expected " + expected + ")");
}

double number(const json& v, const std::string& key) {
  if (!v.is_number()) bad(key, "a number");
  return v.get<double>();
}

std::int64_t integer(const json& v, const std::string& key) {
  if (!v.is_number_integer()) bad(key, "an integer");
  return v.get<std::int64_t>();
}

bool boolean(const json& v, const std::string& key) {
  if (!v.is_boolean()) bad(key, "true or false");
  return v.get<bool>();
}

// plant.noise {"enabled", "inc", "seed"} (drive-core.md §10.8) and plant.regen {"enabled",
// "capacitance_F"} (§10.11).
void optional_features(core::PlantConfig& c, const std::string& section, const json& v) {
  if (!v.is_object()) bad("plant." + section, "an object");
  for (const auto& [key, value] : v.items()) {
    std::string k = "plant." + section;
    k += '.';
    k += key;
    if (section == "noise" && key == "enabled") {
      c.noise.enabled = boolean(value, k);
    } else if (section == "noise" && key == "inc") {
      c.noise.inc = integer(value, k);
    } else if (section == "noise" && key == "seed") {
      if (integer(value, k) < 0) bad(k, "a non-negative integer");
      c.noise.seed = static_cast<std::uint64_t>(value.get<std::int64_t>());
    } else if (section == "regen" && key == "enabled") {
      c.regen.enabled = boolean(value, k);
    } else if (section == "regen" && key == "capacitance_F") {
      c.regen.capacitance_f = number(value, k);
    } else {
      throw ConfigError("unknown key " + k + " in --config");
    }
  }
}

// The keys of the "plant" section (models.md §4, drive-core.md §10.2): most replace a field of the
// preset's model::Plant, in its units (rotary: N·m, kg·m², rpm; linear: N, kg, m/s, mm/s); the
// rest are the settings a preset has no value for (core::PlantConfig).
void plant_keys(core::PlantConfig& c, const json& plant) {
  using Setter = std::function<void(const json&, const std::string&)>;
  using model::Plant;
  const auto real = [&c](double Plant::*field) -> Setter {
    return [&c, field](const json& v, const std::string& k) { c.plant.set(field, number(v, k)); };
  };
  const auto whole = [&c](std::int64_t Plant::*field) -> Setter {
    return [&c, field](const json& v, const std::string& k) { c.plant.set(field, integer(v, k)); };
  };
  const auto flag = [&c](bool Plant::*field) -> Setter {
    return [&c, field](const json& v, const std::string& k) { c.plant.set(field, boolean(v, k)); };
  };
  const std::map<std::string, Setter> keys{
      {"torque_peak", real(&Plant::torque_peak)},
      {"torque_cont", real(&Plant::torque_cont)},
      {"inertia_motor", real(&Plant::inertia_motor)},
      {"inertia_load", real(&Plant::inertia_load)},
      {"viscous", real(&Plant::viscous)},
      {"coulomb", real(&Plant::coulomb)},
      {"no_load_speed", real(&Plant::no_load_speed)},
      {"velocity_bandwidth_hz", real(&Plant::velocity_bandwidth_hz)},
      {"accel_feedforward", real(&Plant::accel_feedforward)},
      {"moving_threshold", real(&Plant::moving_threshold)},
      {"P_idle", real(&Plant::p_idle_w)},
      {"P_cu", real(&Plant::p_cu_w)},
      {"R_th", real(&Plant::r_th_k_per_w)},
      {"tau_th", real(&Plant::tau_th_s)},
      {"supply_nominal_V", real(&Plant::supply_nominal_v)},
      {"uv_V", real(&Plant::supply_uv_v)},
      {"ov_V", real(&Plant::supply_ov_v)},
      {"power_on_position", whole(&Plant::power_on_position_inc)},
      {"following_error_limit", whole(&Plant::following_error_limit_inc)},  // inc, 0 = none
      {"temperature_available", flag(&Plant::temperature_available)},
      {"hw_enable_fitted", flag(&Plant::hw_enable_fitted)},
      {"stops",
       [&](const json& v, const std::string& k) {
         if (v.is_null()) {
           c.plant.set(&Plant::stops_inc, std::optional<core::StopRange>{});
           return;
         }
         if (!v.is_array() || v.size() != 2) bad(k, "[min_inc, max_inc] or null");
         c.plant.set(&Plant::stops_inc, core::StopRange{integer(v[0], k), integer(v[1], k)});
       }},
      {"rotary_accel_unit",  // [num, den] motor rev/s² per unit
       [&](const json& v, const std::string& k) {
         if (!v.is_array() || v.size() != 2 || integer(v[0], k) < 1 || integer(v[1], k) < 1) bad(k, "[num, den] ≥ 1");
         c.plant.set(&Plant::rotary_accel_unit_num, v[0].get<std::int64_t>());
         c.plant.set(&Plant::rotary_accel_unit_den, v[1].get<std::int64_t>());
       }},
      // not in a preset
      {"inertia_ctrl", [&](const json& v, const std::string& k) { c.inertia_ctrl = number(v, k); }},
      {"external_load", [&](const json& v, const std::string& k) { c.external_load = number(v, k); }},
      {"stroke_mm", [&](const json& v, const std::string& k) { c.stroke_mm = number(v, k); }},
      {"position_switches",
       [&](const json& v, const std::string& k) {
         if (!v.is_array()) bad(k, "a list of {\"input\", \"from_inc\", \"to_inc\"}");
         for (const auto& s : v) {
           if (!s.is_object() || !s.contains("input") || !s.contains("from_inc") || !s.contains("to_inc")) {
             bad(k, "a list of {\"input\", \"from_inc\", \"to_inc\"}");
           }
           c.position_switches.push_back(
               {static_cast<int>(integer(s["input"], k)), integer(s["from_inc"], k), integer(s["to_inc"], k)});
         }
       }},
  };
  for (const auto& [key, value] : plant.items()) {
    if (key == "noise" || key == "regen") {
      optional_features(c, key, value);
      continue;
    }
    const auto it = keys.find(key);
    if (it == keys.end()) throw ConfigError("unknown key plant." + key + " in --config");
    it->second(value, "plant." + key);
  }
}

}  // namespace

core::PlantConfig plant_config_from_json(const json& config) {
  core::PlantConfig c;
  if (const auto p = config.find("plant"); p != config.end()) {
    if (!p->is_object()) bad("plant", "an object");
    plant_keys(c, *p);
  }
  if (const auto h = config.find("homing"); h != config.end()) {
    if (!h->is_object()) bad("homing", "an object");
    for (const auto& [key, value] : h->items()) {
      if (key == "max_search_ms") {
        c.homing.max_search_ms = integer(value, "homing.max_search_ms");
      } else if (key == "enable_method_18") {
        c.homing.enable_method_18 = boolean(value, "homing.enable_method_18");
      } else {
        throw ConfigError("unknown key homing." + key + " in --config");
      }
    }
  }
  return c;
}

}  // namespace mcemu::device
