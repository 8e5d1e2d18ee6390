#include "web/api/pages.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "web/api/http_util.hpp"
#include "web/assets/assets.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

// A dotted path ("ports.http", "python.id") into a JSON object.
const json* find_path(const json& root, std::string_view path) {
  const json* at = &root;
  while (!path.empty()) {
    const auto dot = path.find('.');
    const std::string key(path.substr(0, dot));
    if (!at->is_object()) return nullptr;
    const auto it = at->find(key);
    if (it == at->end()) return nullptr;
    at = &*it;
    path = dot == std::string_view::npos ? std::string_view() : path.substr(dot + 1);
  }
  return at;
}

std::string plain(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_null()) return "-";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  return v.dump();
}

// "6081.00" → (0x6081, 0)
std::optional<std::pair<std::uint16_t, std::uint8_t>> object_key(std::string_view key) {
  const auto dot = key.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const auto index = parse_hex_token(key.substr(0, dot), 0xFFFF);
  const auto sub = parse_hex_token(key.substr(dot + 1), 0xFF);
  if (!index || !sub) return std::nullopt;
  return std::pair{static_cast<std::uint16_t>(*index), static_cast<std::uint8_t>(*sub)};
}

std::string script_json_text(const json& j) {
  std::string out;
  for (const char ch : dump_json(j)) {
    if (ch == '<') {
      out += "\\u003c";
    } else if (ch == '>') {
      out += "\\u003e";
    } else if (ch == '&') {
      out += "\\u0026";
    } else {
      out += ch;
    }
  }
  return out;
}

json page_data(const PageContext& ctx) {
  const auto& m = ctx.model;
  const auto* device = find_path(ctx.info, "deviceName");
  return json{{"model", ctx.info.value("model", "")},
              {"shortName", short_model_name(device && device->is_string() ? device->get<std::string>() : "")},
              {"linear", m.linear},
              {"inputPins", m.input_pins},
              {"outputPins", m.output_pins},
              {"temperatureAvailable", m.temperature_available},
              {"supply", {{"nominalV", m.supply_nominal_v}, {"underV", m.supply_uv_v}, {"overV", m.supply_ov_v}}},
              {"accelerationUnit", acceleration_unit_text(m)}};
}

std::string python_state(const PageContext& ctx) {
  if (ctx.script) return ctx.script->state;
  const auto* s = find_path(ctx.status, "python.state");
  return s && s->is_string() ? s->get<std::string>() : "OFF";
}

bool autostart(const PageContext& ctx) {
  if (ctx.script) return ctx.script->autostart;
  const auto* a = find_path(ctx.status, "python.autostart");
  return a && a->is_boolean() && a->get<bool>();
}

// The value of one key as HTML, nullopt for a key this renderer does not know.
std::optional<std::string> value_of(std::string_view key, const PageContext& ctx) {
  const auto prefixed = [&](std::string_view p) { return key.substr(0, p.size()) == p; };
  if (prefixed("info.") || prefixed("status.")) {
    const bool info = prefixed("info.");
    const auto* v = find_path(info ? ctx.info : ctx.status, key.substr(info ? 5 : 7));
    if (!v) return std::nullopt;
    return html_escape(plain(*v));
  }
  if (key == "footer.live") {
    const auto* v = find_path(ctx.status, "footer.live");
    const std::string text = v && v->is_string() ? v->get<std::string>() : "";
    constexpr std::string_view err = "MC Live ERR";
    if (text.substr(0, err.size()) == err) {
      return "MC Live <a href=\"/index.html\" class=\"err\">" + html_escape(text.substr(8)) + "</a>";
    }
    return html_escape(text);
  }
  if (prefixed("footer.")) {
    const auto* v = find_path(ctx.status, key);
    if (!v || !v->is_string()) return std::nullopt;
    return html_escape(v->get<std::string>());
  }
  if (key == "led.green" || key == "led.yellow") {
    const auto* v = find_path(ctx.status, key);
    return v && v->is_boolean() && v->get<bool>() ? "1" : "0";
  }
  if (key == "model.short") {
    const auto* v = find_path(ctx.info, "deviceName");
    return html_escape(short_model_name(v && v->is_string() ? v->get<std::string>() : ""));
  }
  if (key == "model.accelerationUnit") return html_escape(acceleration_unit_text(ctx.model));
  if (key == "lastError") {
    const auto* v = find_path(ctx.status, "lastError.text");
    return html_escape(v && v->is_string() ? v->get<std::string>() : "-");
  }
  if (prefixed("od.") || prefixed("odh.")) {
    const bool hex = prefixed("odh.");
    const auto k = object_key(key.substr(hex ? 4 : 3));
    if (!k) return std::nullopt;
    const auto v = ctx.object ? ctx.object(k->first, k->second) : std::nullopt;
    if (!v) return std::string();
    if (hex && v->is_number_integer()) {
      return h4(static_cast<std::uint32_t>(v->get<std::int64_t>()));
    }
    return html_escape(plain(*v));
  }
  if (key == "code.status") {
    const auto* id = find_path(ctx.status, "python.id");
    const std::string name = ctx.script ? ctx.script->id : (id && id->is_string() ? id->get<std::string>() : "");
    return html_escape(python_state(ctx) + " " + name);
  }
  if (key == "code.autoOn") return std::string(autostart(ctx) ? "ON [X]" : "ON");
  if (key == "code.autoOff") return std::string(autostart(ctx) ? "OFF" : "OFF [X]");
  if (key == "code.viewer") return ctx.script ? html_escape(ctx.script->source) : std::string();
  if (key == "code.engine") {
    if (!ctx.script) {
      return std::string(
          "The script engine is not available in this version of mcemu: uploading, running, stopping and autostart "
          "are switched off. RefGo, CANopen, the I/O functions and every other page work as usual.");
    }
    const auto* e = find_path(ctx.info, "scripting.engine");
    const auto* reason = find_path(ctx.info, "scripting.reason");
    const auto* unsafe = find_path(ctx.info, "scripting.sandbox.unsafe");
    if (!(e && e->is_string()) && reason && reason->is_string()) {  // unavailable: say why
      return html_escape("The script engine is not available: " + reason->get<std::string>() + ".");
    }
    std::string text = "Script engine: " + (e && e->is_string() ? e->get<std::string>() : std::string("available"));
    if (unsafe && unsafe->is_boolean() && unsafe->get<bool>()) {
      const auto* why = find_path(ctx.info, "scripting.sandbox.reason");
      if (why && why->is_string()) text += ". " + why->get<std::string>() + ".";
    }
    return html_escape(text);
  }
  if (key == "page.data") return script_json_text(page_data(ctx));
  return std::nullopt;
}

// Calls on_key(key, start, end) for every {{key}} and on_text(text) for the text between them.
template <typename OnText, typename OnKey>
void scan(std::string_view tmpl, OnText on_text, OnKey on_key) {
  std::size_t at = 0;
  while (at < tmpl.size()) {
    const auto open = tmpl.find("{{", at);
    const auto close = open == std::string_view::npos ? open : tmpl.find("}}", open + 2);
    if (close == std::string_view::npos) {
      on_text(tmpl.substr(at));
      return;
    }
    on_text(tmpl.substr(at, open - at));
    on_key(tmpl.substr(open + 2, close - open - 2), tmpl.substr(open, close + 2 - open));
    at = close + 2;
  }
}

void render_into(std::string& out, std::string_view tmpl, const PageContext& ctx, const PartialLookup& partials,
                 int depth, std::vector<std::string>* unknown) {
  scan(
      tmpl, [&](std::string_view text) { out += text; },
      [&](std::string_view raw_key, std::string_view whole) {
        const auto key = trim(raw_key);
        if (key.substr(0, 1) == ">") {
          const auto name = trim(key.substr(1));
          const auto partial = depth == 0 && partials ? partials(name) : std::nullopt;
          if (partial) return render_into(out, *partial, ctx, partials, depth + 1, unknown);
          if (unknown) unknown->emplace_back(key);
          out += whole;
          return;
        }
        if (const auto v = value_of(key, ctx)) {
          out += *v;
          return;
        }
        if (unknown) unknown->emplace_back(key);
        out += whole;
      });
}

}  // namespace

PartialLookup embedded_partials() {
  return [](std::string_view name) -> std::optional<std::string_view> {
    const auto* a = assets::find("/static/partials/" + std::string(name) + ".html");
    if (!a) return std::nullopt;
    return a->bytes;
  };
}

std::string render_page(std::string_view tmpl, const PageContext& ctx, const PartialLookup& partials) {
  std::string out;
  out.reserve(tmpl.size() + 1024);
  render_into(out, tmpl, ctx, partials, 0, nullptr);
  return out;
}

std::vector<std::string> unknown_keys(std::string_view tmpl, const PageContext& ctx, const PartialLookup& partials) {
  std::string sink;
  std::vector<std::string> unknown;
  render_into(sink, tmpl, ctx, partials, 0, &unknown);
  return unknown;
}

std::string acceleration_unit_text(const PageModel& m) {
  if (m.linear) return "1 unit = 1000 user position units/s²";
  const double per_min2 = m.rotary_accel_unit_den == 0 ? 0.0
                                                       : 3600.0 * static_cast<double>(m.rotary_accel_unit_num) /
                                                             static_cast<double>(m.rotary_accel_unit_den);
  char buf[32];
  if (std::abs(per_min2 - std::round(per_min2)) < 1e-9) {
    std::snprintf(buf, sizeof buf, "%.0f", per_min2);
  } else {
    std::snprintf(buf, sizeof buf, "%.4g", per_min2);
  }
  return std::string("1 unit = ") + buf + " motor rev/min²";
}

std::string short_model_name(std::string_view device_name) {
  const auto at = device_name.find("_ETH");
  return std::string(device_name.substr(0, at));
}

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += ch;
    }
  }
  return out;
}

}  // namespace mcemu::web::api
