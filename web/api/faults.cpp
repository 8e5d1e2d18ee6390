#include "web/api/faults.hpp"

#include <algorithm>

#include "drive/drive_core.hpp"
#include "drive/faults.hpp"
#include "drive/od/hex.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

// The ambient temperature the drive core starts with (drive-core.md §10.7).
constexpr double k_default_ambient_c = 25.0;

Response json_response(int status, const json& body) {
  Response r;
  r.status = status;
  r.body = body.dump();
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

Response bad(const std::string& message) {
  return json_response(400, json{{"error", {{"code", "syntax"}, {"message", message}}}});
}

std::optional<double> number(const json& body, const char* key) {
  if (!body.contains(key) || !body[key].is_number()) return std::nullopt;
  return body[key].get<double>();
}

// "7121h", "0x7121", "7121" (hex) or an integer.
std::optional<std::uint16_t> emcy_code(const json& v) {
  if (v.is_number_unsigned() && v.get<std::uint64_t>() <= 0xFFFF)
    return static_cast<std::uint16_t>(v.get<std::uint64_t>());
  if (!v.is_string()) return std::nullopt;
  std::string_view t = v.get_ref<const std::string&>();
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t.remove_prefix(2);
  } else if (!t.empty() && (t.back() == 'h' || t.back() == 'H')) {
    t.remove_suffix(1);
  }
  const auto code = od::parse_hex(t, 0xFFFF);
  if (!code) return std::nullopt;
  return static_cast<std::uint16_t>(*code);
}

}  // namespace

Response FaultInjections::create(const std::string& text) {
  const json body = json::parse(text, nullptr, false);
  if (body.is_discarded() || !body.is_object() || !body.contains("kind") || !body["kind"].is_string()) {
    return bad("expected {\"kind\": \"…\", …}");
  }
  const std::string kind = body["kind"].get<std::string>();
  if (body.contains("count")) return bad("\"count\" is not available for kind " + kind + " in this version");
  std::optional<std::uint64_t> expires;
  if (body.contains("durationMs")) {
    if (!body["durationMs"].is_number_unsigned() || body["durationMs"].get<std::uint64_t>() == 0) {
      return bad("\"durationMs\" must be a positive integer (drive time)");
    }
    expires = core_.time_ms() + body["durationMs"].get<std::uint64_t>();
  }

  Injection inj;
  inj.description = body;
  if (kind == "drive.inject") {
    const auto cause = body.contains("cause") && body["cause"].is_string()
                           ? core::fault_cause_from_string(body["cause"].get<std::string>())
                           : std::nullopt;
    if (!cause) return bad("drive.inject needs \"cause\": one of the names of drive-core.md §11.1");
    core_.inject(*cause);
    inj.undo = [this, c = *cause] { core_.clear(c); };
  } else if (kind == "drive.emcy") {
    const auto code = body.contains("code") ? emcy_code(body["code"]) : std::nullopt;
    if (!code) return bad("drive.emcy needs \"code\", e.g. \"7121h\"");
    const auto table = core::fault_table();
    const auto it = std::find_if(table.begin(), table.end(),
                                 [&](const core::FaultInfo& f) { return f.code == *code && f.code != 0; });
    if (it == table.end()) return bad("no drive fault has the EMCY code " + body["code"].dump());
    // One shot: the cause is present for one drive step, so that the step's fault check sees it;
    // the fault itself stays until a fault reset (drive-core.md §11.9).
    core_.inject(it->cause);
    inj.undo = [this, c = it->cause] { core_.clear(c); };
    expires = core_.time_ms() + 1;
  } else if (kind == "drive.supply") {
    const auto v = number(body, "volts");
    if (!v) return bad("drive.supply needs \"volts\"");
    core_.set_supply_voltage(*v);
    inj.undo = [this] { core_.set_supply_voltage(core_.plant_params().supply_nominal_v); };
  } else if (kind == "drive.ambient") {
    const auto v = number(body, "celsius");
    if (!v) return bad("drive.ambient needs \"celsius\"");
    core_.set_ambient_temperature(*v);
    inj.undo = [this] { core_.set_ambient_temperature(k_default_ambient_c); };
  } else if (kind == "drive.load") {
    const auto v = number(body, "value");
    if (!v) return bad("drive.load needs \"value\" (N·m or N)");
    core_.set_external_load(*v);
    inj.undo = [this] { core_.set_external_load(0); };
  } else if (kind == "drive.obstacle") {
    if (!body.contains("positionInc") || !body["positionInc"].is_number_integer() || !body.contains("side") ||
        !body["side"].is_number_integer() || (body["side"] != 1 && body["side"] != -1)) {
      return bad("drive.obstacle needs \"positionInc\" (integer) and \"side\" (+1 or -1)");
    }
    const auto id =
        core_.add_obstacle(core::Obstacle{body["positionInc"].get<std::int64_t>(), body["side"].get<int>()});
    inj.undo = [this, id] { core_.remove_obstacle(id); };
  } else {
    return bad("fault kind \"" + kind + "\" is not available in this version");
  }
  inj.id = "f" + std::to_string(next_id_++);
  inj.expires = expires;
  inj.description["id"] = inj.id;
  json answer = inj.description;
  active_.push_back(std::move(inj));
  return json_response(201, answer);
}

Response FaultInjections::list() const {
  json all = json::array();
  for (const auto& i : active_) all.push_back(i.description);
  return json_response(200, json{{"faults", all}});
}

void FaultInjections::undo(Injection& i) {
  if (i.undo) i.undo();
}

Response FaultInjections::remove(const std::string& id) {
  const auto it = std::find_if(active_.begin(), active_.end(), [&](const Injection& i) { return i.id == id; });
  if (it == active_.end()) {
    return json_response(404, json{{"error", {{"code", "not-found"}, {"message", "no active injection " + id}}}});
  }
  undo(*it);
  active_.erase(it);
  return json_response(200, json{{"ok", true}});
}

Response FaultInjections::remove_all() {
  for (auto& i : active_) undo(i);
  active_.clear();
  return json_response(200, json{{"ok", true}});
}

void FaultInjections::on_step() {
  const auto now = core_.time_ms();
  for (auto it = active_.begin(); it != active_.end();) {
    if (it->expires && *it->expires <= now) {
      undo(*it);
      it = active_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace mcemu::web::api
