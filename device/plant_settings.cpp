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

void plant_keys(core::PlantConfig& c, const json& plant) {
  using Setter = std::function<void(const json&, const std::string&)>;
  const auto real = [](std::optional<double>& field) -> Setter {
    return [&field](const json& v, const std::string& k) { field = number(v, k); };
  };
  const std::map<std::string, Setter> keys{
      {"torque_peak", real(c.torque_peak)},
      {"torque_cont", real(c.torque_cont)},
      {"inertia_motor", real(c.inertia_motor)},
      {"inertia_load", real(c.inertia_load)},
      {"inertia_ctrl", real(c.inertia_ctrl)},
      {"viscous", real(c.viscous)},
      {"coulomb", real(c.coulomb)},
      {"no_load_speed", real(c.no_load_speed)},
      {"velocity_bandwidth_hz", real(c.velocity_bandwidth_hz)},
      {"accel_feedforward", real(c.accel_feedforward)},
      {"external_load", real(c.external_load)},
      {"stroke_mm", real(c.stroke_mm)},
      {"moving_threshold", real(c.moving_threshold)},
      {"P_idle", real(c.p_idle_w)},
      {"P_cu", real(c.p_cu_w)},
      {"R_th", real(c.r_th_k_per_w)},
      {"tau_th", real(c.tau_th_s)},
      {"supply_nominal_V", real(c.supply_nominal_v)},
      {"uv_V", real(c.supply_uv_v)},
      {"ov_V", real(c.supply_ov_v)},
      {"power_on_position", [&](const json& v, const std::string& k) { c.power_on_position = integer(v, k); }},
      {"following_error_limit", [&](const json& v, const std::string& k) { c.following_error_limit = integer(v, k); }},
      {"temperature_available", [&](const json& v, const std::string& k) { c.temperature_available = boolean(v, k); }},
      {"hw_enable_fitted", [&](const json& v, const std::string& k) { c.hw_enable_fitted = boolean(v, k); }},
      {"stops",
       [&](const json& v, const std::string& k) {
         if (v.is_null()) {
           c.stops = std::optional<core::StopRange>{};
           return;
         }
         if (!v.is_array() || v.size() != 2) bad(k, "[min_inc, max_inc] or null");
         c.stops = std::optional<core::StopRange>{core::StopRange{integer(v[0], k), integer(v[1], k)}};
       }},
      {"rotary_accel_unit",
       [&](const json& v, const std::string& k) {
         if (!v.is_array() || v.size() != 2 || integer(v[0], k) < 1 || integer(v[1], k) < 1) bad(k, "[num, den] ≥ 1");
         c.rotary_accel_unit = {static_cast<std::uint64_t>(v[0].get<std::int64_t>()),
                                static_cast<std::uint64_t>(v[1].get<std::int64_t>())};
       }},
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
