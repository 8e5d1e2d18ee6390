// Router handlers that act on the drive: info, status, objects, RefGo, I/O, store/reset, power
// cycle, EDS, the OpenAPI document (web.md §7, §8.1–§8.5, §8.8).
#include <algorithm>

#include "drive/od/objects.hpp"
#include "protocols/line/line_assembler.hpp"
#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "web/api/http_util.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

Response bad(const std::string& message) { return error_json(400, "syntax", message); }

std::string value_text(const od::Value& v) {
  if (const auto* n = std::get_if<std::int64_t>(&v)) return std::to_string(*n);
  return dump_json(json(std::get<std::string>(v)));
}

// "ok" or the abort code of a write, for the journal.
std::string outcome(od::AbortCode code) { return code == od::AbortCode::none ? std::string("ok") : abort_hex(code); }

// The answer line of a RefGo reply "<echo>\r\n[<answer>\r\n]>" (refgo.md §3), if any.
std::optional<std::string> answer_line(std::string_view reply) {
  const auto first = reply.find("\r\n");
  if (first == std::string_view::npos) return std::nullopt;
  const auto rest = reply.substr(first + 2);
  const auto second = rest.find("\r\n");
  if (second == std::string_view::npos) return std::nullopt;
  return std::string(rest.substr(0, second));
}

}  // namespace

bool Router::empty_body(const Ctx& c) {
  const auto body = json_object_body(c.req);
  if (body && body->empty()) return true;
  c.respond(bad(body ? "\"" + body->begin().key() + "\": unknown field (the body is {})" : "expected {} as the body"));
  return false;
}

nlohmann::json Router::info_json() const {
  const Info i = services_.info ? services_.info() : Info{};
  const ClockInfo clock = clock_info();
  // scripting.md §10.1.8: the engine and its version, or why it is unavailable
  const bool available = services_.script && services_.script->available();
  json scripting{{"available", available}, {"engine", available ? json(services_.script->engine()) : json(nullptr)}};
  if (services_.script && !available) scripting["reason"] = services_.script->engine();
  // The services of the drive's personality (a FAULHABER MC has neither RefGo, SLCAN nor UDP).
  json ports = json::object();
  const auto& personality = device_.personality();
  if (personality.refgo) ports["refgo"] = i.refgo_port;
  if (personality.canopen) ports["slcan"] = i.slcan_port;
  ports["http"] = i.http_port;
  if (personality.udp_debug) ports["udp"] = i.udp_port;
  if (personality.faulhaber) {
    ports["faulhaber"] = i.faulhaber_port;
    if (!i.faulhaber_pty.empty()) ports["faulhaberPty"] = i.faulhaber_pty;
  }
  // docs/security.md: whether scripts run in the OS sandbox, and what it is or why there is none
  if (const SandboxView sb = services_.script ? services_.script->sandbox() : SandboxView{}; sb.known) {
    scripting["sandbox"] =
        json{{"active", sb.active}, {"unsafe", sb.unsafe}, {sb.active ? "description" : "reason", sb.text}};
  }
  json doc{{"emulator", "mcemu"},
           {"personality", personality.name},
           {"version", i.version},
           {"model", i.model},
           {"displayName", i.display_name},
           {"deviceName", i.device_name},
           {"softwareVersion", i.software_version},
           {"serial", i.serial}};
  // The drive's own IP address and mask (5007h/5008h, --ip): a drive without them — a FAULHABER MC,
  // reached over RS232 — has none, and "bind"/"ports" say where mcemu listens for it.
  if (device_.od().find(od::k_ip_address, 1)) doc["ip"] = i.ip;
  if (device_.od().find(od::k_ip_mask, 1)) doc["mask"] = i.mask;
  doc.update(json{{"bind", i.bind},
                  {"ports", ports},
                  {"stateDir", i.state_dir},
                  {"scripting", scripting},
                  {"clock", {{"mode", clock.mode}, {"scale", scale_json(clock.scale)}}},
                  // docs/lint.md §5: the master lint's mode and whether its timing rules judge
                  {"lint",
                   {{"mode", lint::to_string(device_.lint().engine().config().mode)},
                    {"timing", device_.lint().engine().config().timing}}}});
  return doc;
}

std::string Router::info_text() const { return dump_json(info_json()); }

void Router::get_info(const Ctx& c) { c.respond(json_response(200, info_json())); }

void Router::get_status(const Ctx& c) {
  Response r;
  r.body = status_text();
  r.headers.emplace_back("Cache-Control", "no-store");
  c.respond(std::move(r));
}

namespace {

void append_value(std::string& out, const od::Value& v) {
  if (const auto* n = std::get_if<std::int64_t>(&v)) {
    out += std::to_string(*n);
  } else {
    out += dump_json(json(std::get<std::string>(v)));  // nlohmann's escaping and UTF-8 repair
  }
}

// One entry of web.md §8.3 as dump_json() prints its document ({access, factory, index, name, sub,
// type, value}: the document's keys are sorted), written straight into `out`. GET /api/v1/objects
// writes ~700 of them a request; building the document first took ~1 ms and most of its
// allocations. The texts of the tables (access, type, hex numbers) need no escaping.
void append_entry_json(std::string& out, const od::ObjectDictionary& od, const od::EntryInfo& e,
                       const std::function<std::optional<od::Value>(std::uint16_t, std::uint8_t)>& factory) {
  out += R"({"access":")";
  out += od::to_string(e.access);
  out += R"(","factory":)";
  const auto f = factory ? factory(e.index, e.sub) : std::nullopt;
  append_value(out, f ? *f : e.factory);
  out += R"(,"index":")";
  out += hex_index(e.index);
  out += R"(","name":)";
  out += dump_json(json(std::string(e.name)));
  out += R"(,"sub":")";
  out += hex_sub(e.sub);
  out += R"(","type":")";
  out += od::to_string(e.type);
  out += R"(","value":)";
  if (const auto v = od.read(e.index, e.sub)) {
    append_value(out, *v);
  } else {
    out += "null";
  }
  out += '}';
}

}  // namespace

void Router::get_objects(const Ctx& c) {
  std::string body = "[";
  body.reserve(100 * device_.od().size());
  device_.od().for_each([&](const od::EntryInfo& e, const od::Value&) {
    if (body.size() > 1) body += ',';
    append_entry_json(body, device_.od(), e, services_.factory);
  });
  body += ']';
  c.respond(text_response(200, "application/json", std::move(body)));
}

void Router::get_object(const Ctx& c) {
  const auto index = parse_hex_token(c.params[0], 0xFFFF);
  const auto sub = parse_hex_token(c.params[1], 0xFF);
  if (!index || !sub) return c.respond(bad("object index and sub-index are hex numbers"));
  const auto i = static_cast<std::uint16_t>(*index);
  const auto s = static_cast<std::uint8_t>(*sub);
  const auto v = device_.od().read(i, s);
  if (!v) return c.respond(abort_response(v.error()));
  std::string body;
  append_entry_json(body, device_.od(), *device_.od().info(i, s), services_.factory);
  c.respond(text_response(200, "application/json", std::move(body)));
}

void Router::put_object(const Ctx& c) {
  const auto index = parse_hex_token(c.params[0], 0xFFFF);
  const auto sub = parse_hex_token(c.params[1], 0xFF);
  if (!index || !sub) return c.respond(bad("object index and sub-index are hex numbers"));
  const auto body = json_object_body(c.req);
  if (!body || !body->contains("value") || !((*body)["value"].is_number_integer() || (*body)["value"].is_string())) {
    return c.respond(bad("expected {\"value\": <integer or string>}"));
  }
  const auto& jv = (*body)["value"];
  if (jv.is_number_unsigned() && jv.get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
    return c.respond(bad("\"value\" is out of range"));
  }
  const auto i = static_cast<std::uint16_t>(*index);
  const auto s = static_cast<std::uint8_t>(*sub);
  const od::Value value = jv.is_string() ? od::Value{jv.get<std::string>()} : od::Value{jv.get<std::int64_t>()};
  const std::string what = "PUT " + hex_index(i) + "." + hex_sub(s) + " = " + value_text(value);
  if (jv.is_number()) {  // the JSON API is strict: no two's complement (object-dictionary.md §3.2)
    const auto* info = device_.od().info(i, s);
    if (const auto code = out_of_type_range(info, jv.get<std::int64_t>())) {
      journal(c.req, what + " " + outcome(*code));
      return c.respond(range_error(*info, jv.get<std::int64_t>(), *code));
    }
  }
  auto finish = [this, alive = alive_.watch(), i, s, what, respond = c.respond, conn = c.req.conn,
                 peer = c.req.peer](od::AbortCode code) {
    if (alive) journal_text(conn, peer, what + " " + outcome(code));
    if (code != od::AbortCode::none) return respond(abort_response(code));
    const auto v = alive ? device_.od().read(i, s) : od::Result<od::Value>(od::AbortCode::general);
    respond(json_response(200, json{{"ok", true}, {"value", v ? value_json(*v) : json(nullptr)}}));
  };
  const auto code = device_.od().write(i, s, value, od::Origin::web, finish);
  if (code != od::AbortCode::pending) finish(code);
}

void Router::post_objects_read(const Ctx& c) {
  const auto body = json_object_body(c.req);
  if (!body || !body->contains("objects") || !(*body)["objects"].is_array()) {
    return c.respond(bad("expected {\"objects\": [[index, sub], …]}"));
  }
  json values = json::array();
  for (const auto& item : (*body)["objects"]) {
    std::optional<std::uint32_t> index;
    std::optional<std::uint32_t> sub;
    if (item.is_array() && item.size() == 2) {
      index = json_hex_or_number(item[0], 0xFFFF);
      sub = json_hex_or_number(item[1], 0xFF);
    }
    if (!index || !sub) return c.respond(bad("bad object reference " + dump_json(item)));
    const auto v = device_.od().read(static_cast<std::uint16_t>(*index), static_cast<std::uint8_t>(*sub));
    values.push_back(v ? value_json(*v) : json{{"abortCode", abort_hex(v.error())}});
  }
  c.respond(json_response(200, json{{"values", values}}));
}

void Router::post_refgo(const Ctx& c) {
  if (!device_.refgo()) {  // a FAULHABER MC has no RefGo (faulhaber.md §1)
    return c.respond(error_json(503, "unavailable", "this drive has no RefGo interpreter"));
  }
  const auto body = json_object_body(c.req);
  if (!body || !body->contains("line") || !(*body)["line"].is_string()) {
    return c.respond(bad("expected {\"line\": \"<one RefGo line>\"}"));
  }
  const std::string& line = (*body)["line"].get_ref<const std::string&>();
  if (line.find_first_of("\r\n") != std::string::npos) {
    return c.respond(bad("\"line\" must not contain CR or LF (one line without terminator)"));
  }
  // The same framing as on TCP (refgo.md §2.3, §2.4): control bytes filtered, 255 bytes at most.
  line::LineAssembler assembler(refgo::k_max_line, refgo::filter_byte);
  const auto lines = assembler.feed(line + "\r");
  const line::Line framed = lines.empty() ? line::Line{} : lines.front();
  const auto answer = [](const std::string& reply) {
    const auto a = answer_line(reply);
    const bool ok = !a || a->find(",ERROR,") == std::string::npos;
    return json{{"reply", reply}, {"answer", a ? json(*a) : json(nullptr)}, {"ok", ok}};
  };
  if (framed.overlong) {
    journal(c.req, "refgo (over-long line, " + std::to_string(line.size()) + " bytes) -> >");
    return c.respond(json_response(200, answer(">")));
  }
  auto done = [this, alive = alive_.watch(), answer, respond = c.respond, conn = c.req.conn, peer = c.req.peer,
               text = framed.text](const std::string& reply) {
    if (alive) journal_text(conn, peer, "refgo " + dump_json(json(text)) + " -> " + dump_json(json(reply)));
    respond(json_response(200, answer(reply)));
  };
  if (auto reply = device_.refgo()->execute(framed.text, done)) done(*reply);
}

json Router::io_json() const {
  const auto number = [&](std::uint16_t i, std::uint8_t s) {
    const auto v = device_.od().read_number(i, s);
    return v ? *v : 0;
  };
  return json{{"effective", number(od::k_digital_inputs, 0)},
              {"physical", device_.core().physical_inputs()},
              {"virtual", number(od::k_io_simulation, od::k_virtual_inputs)},
              {"outputs", number(od::k_digital_outputs, 1)}};
}

void Router::get_io(const Ctx& c) { c.respond(json_response(200, io_json())); }

void Router::put_physical_inputs(const Ctx& c) {
  const auto body = json_object_body(c.req);
  if (!body) return c.respond(bad("expected {\"mask\": n} or {\"set\": […], \"clear\": […]}"));
  for (const auto& [key, value] : body->items()) {
    if (key != "mask" && key != "set" && key != "clear") return c.respond(bad("\"" + key + "\": unknown field"));
  }
  std::array<std::optional<bool>, 11> want{};  // index 1…10
  if (body->contains("mask")) {
    if (body->contains("set") || body->contains("clear"))
      return c.respond(bad("\"mask\" or \"set\"/\"clear\", not both"));
    const auto mask = json_uint((*body)["mask"], 0, 0xFFFFFFFF);
    if (!mask || (*mask & ~0x03FF0000ULL) != 0) return c.respond(bad("\"mask\": bits 16…25 (IN1…IN10) only"));
    for (int n = 1; n <= 10; ++n) want[static_cast<std::size_t>(n)] = ((*mask >> (15 + n)) & 1U) != 0;
  } else if (body->contains("set") || body->contains("clear")) {
    for (const char* key : {"set", "clear"}) {
      if (!body->contains(key)) continue;
      const auto& list = (*body)[key];
      if (!list.is_array()) return c.respond(bad(std::string("\"") + key + "\": a list of input numbers 1 … 10"));
      for (const auto& item : list) {
        const auto n = json_uint(item, 1, 10);
        if (!n) return c.respond(bad(std::string("\"") + key + "\": input numbers are 1 … 10"));
        auto& slot = want[static_cast<std::size_t>(*n)];
        const bool high = std::string_view(key) == "set";
        if (slot && *slot != high) return c.respond(bad("IN" + std::to_string(*n) + " is both in set and clear"));
        slot = high;
      }
    }
  } else {
    return c.respond(bad("expected {\"mask\": n} or {\"set\": […], \"clear\": […]}"));
  }
  // Check every pin first, so that a refused request changes nothing (iofunc.md §2.1).
  const auto& pins = device_.preset().input_pins;
  const bool by_mask = body->contains("mask");
  for (int n = 1; n <= 10; ++n) {
    const auto& w = want[static_cast<std::size_t>(n)];
    if (!w || std::find(pins.begin(), pins.end(), n) != pins.end()) continue;
    if (by_mask && !*w) continue;  // a mask's 0 for a pin-less input is what that input already reads
    return c.respond(
        error_json(409, "conflict", "IN" + std::to_string(n) + " has no pin on model " + device_.preset().name));
  }
  for (int n = 1; n <= 10; ++n) {
    const auto& w = want[static_cast<std::size_t>(n)];
    if (w && std::find(pins.begin(), pins.end(), n) != pins.end()) device_.core().set_external_input_level(n, *w);
  }
  json j = io_json();
  journal(c.req, "PUT io/physical-inputs " + dump_json(*body) + " -> physical " +
                     std::to_string(j["physical"].get<std::uint32_t>()));
  c.respond(json_response(200, j));
}

void Router::store_or_reset(const Ctx& c, bool store) {
  if (!empty_body(c)) return;
  const std::string what = store ? "store" : "factory-reset";
  auto finish = [this, alive = alive_.watch(), what, respond = c.respond, conn = c.req.conn,
                 peer = c.req.peer](od::AbortCode code) {
    if (alive) journal_text(conn, peer, what + " " + outcome(code));
    if (code != od::AbortCode::none) return respond(abort_response(code));
    respond(json_response(200, json{{"ok", true}}));
  };
  const auto code =
      device_.od().write(store ? od::k_store_parameters : od::k_restore_defaults, 1,
                         od::Value{store ? od::k_save_signature : od::k_load_signature}, od::Origin::web, finish);
  if (code != od::AbortCode::pending) finish(code);
}

void Router::post_store(const Ctx& c) { store_or_reset(c, true); }
void Router::post_factory_reset(const Ctx& c) { store_or_reset(c, false); }

void Router::post_power_cycle(const Ctx& c) {
  if (!empty_body(c)) return;
  if (!services_.power_cycle) {
    return c.respond(error_json(503, "unavailable", "power cycle not available in this configuration"));
  }
  journal(c.req, "power-cycle");
  services_.power_cycle([this, alive = alive_.watch(), respond = c.respond] {
    json j{{"ok", true}};
    if (alive) j["timeMs"] = device_.core().time_ms();
    respond(json_response(200, j));
  });
}

void Router::get_eds(const Ctx& c) {
  if (!services_.eds)
    return c.respond(error_json(503, "unavailable", "EDS export not available in this configuration"));
  c.respond(text_response(200, "text/plain; charset=utf-8", services_.eds()));
}

void Router::get_openapi(const Ctx& c) { c.respond(json_response(200, openapi())); }

void Router::get_ws(const Ctx& c) {
  auto r = error_json(426, "upgrade", "/api/v1/ws is a WebSocket: send an Upgrade: websocket request (web.md §10)");
  r.headers.emplace_back("Upgrade", "websocket");
  c.respond(std::move(r));
}

}  // namespace mcemu::web::api
