#include "web/api/router.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <unordered_map>

#include "protocols/refgo/interpreter.hpp"
#include "trace/trace.hpp"
#include "web/api/http_util.hpp"
#include "web/api/static_files.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

constexpr std::string_view k_value_body = R"({"type":"object","required":["value"],
  "properties":{"value":{"oneOf":[{"type":"integer"},{"type":"string"}]}}})";
constexpr std::string_view k_read_body = R"({"type":"object","required":["objects"],
  "properties":{"objects":{"type":"array","items":{"type":"array","minItems":2,"maxItems":2}}}})";
constexpr std::string_view k_refgo_body = R"({"type":"object","required":["line"],
  "properties":{"line":{"type":"string","description":"one RefGo line without CR/LF"}}})";
constexpr std::string_view k_inputs_body = R"({"type":"object","properties":{
  "mask":{"type":"integer","description":"wire levels IN1…IN10 as bits 16…25"},
  "set":{"type":"array","items":{"type":"integer","minimum":1,"maximum":10}},
  "clear":{"type":"array","items":{"type":"integer","minimum":1,"maximum":10}}}})";
constexpr std::string_view k_empty_body = R"({"type":"object"})";
constexpr std::string_view k_settings_body = R"({"type":"object","additionalProperties":false,"properties":{
  "udpEmulatorNotes":{"type":"boolean"},"scriptStrict":{"type":"boolean"},
  "scriptMemoryMiB":{"type":"integer","minimum":0},"traceScriptCalls":{"type":"boolean"}}})";
constexpr std::string_view k_advance_body = R"({"type":"object","required":["ms"],
  "properties":{"ms":{"type":"integer","minimum":1,"maximum":3600000}}})";
constexpr std::string_view k_fault_body = R"({"type":"object","required":["kind"],"properties":{
  "kind":{"type":"string","enum":["drive.inject","drive.emcy","drive.supply","drive.ambient","drive.load",
    "drive.obstacle","refgo.noReply","refgo.delay","refgo.disconnect","udp.drop","http.error","script.kill",
    "slcan.dropTx","slcan.delayTx","slcan.sdoAbort","slcan.sdoNoReply","slcan.heartbeatStop","slcan.rawTx",
    "slcan.bel","slcan.disconnect"]},
  "count":{"type":"integer","minimum":1},"durationMs":{"type":"integer","minimum":1}}})";
constexpr std::string_view k_autostart_program_body = R"({"type":"object","required":["program"],
  "properties":{"program":{"type":"integer","minimum":0,"maximum":8}}})";
constexpr std::string_view k_levels_body = R"({"type":"object","required":["levels"],
  "properties":{"levels":{"type":"integer","minimum":0,"maximum":255,"description":"bit 0 = DigIn1"}}})";
constexpr std::string_view k_autostart_body = R"({"type":"object","required":["on"],
  "properties":{"on":{"type":"boolean"}}})";

const Answer k_400{400, "malformed request (syntax)"};
const Answer k_404{404, "object or sub-index does not exist"};
const Answer k_409{409, "refused (SDO abort code or state)"};
const Answer k_415{415, "POST without Content-Type: application/json"};
const Answer k_503{503, "not available in this version or this configuration"};
const Answer k_201{201, "created"};
const Answer k_503_engine{503, "no script engine in this build"};

// web/README.md "FAULHABER drive": a drive without the MovingCap pages (faulhaber.md §1) serves its
// own Emulator page, the template /faulhaber.html, at /emulator.html; `/` and the MovingCap pages
// redirect there. A MovingCap does not serve that template.
constexpr std::string_view k_fh_emulator_template = "/faulhaber.html";
constexpr std::array<std::string_view, 9> k_movingcap_pages{
    "/",           "/index.html",   "/clickrun.html", "/servo.html",  "/ioin.html",
    "/ioout.html", "/command.html", "/program.html",  "/network.html"};

bool is_movingcap_page(std::string_view path) {
  return std::find(k_movingcap_pages.begin(), k_movingcap_pages.end(), path) != k_movingcap_pages.end();
}

Response redirect_to(std::string_view location) {
  Response r;
  r.status = 302;
  r.content_type = "text/html; charset=utf-8";
  r.body = "<!DOCTYPE html><html><head><title>302 Found</title></head><body><p>This drive's page is <a href=\"" +
           std::string(location) + "\">" + std::string(location) + "</a>.</p></body></html>\n";
  r.headers.emplace_back("Location", std::string(location));
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

// "comma-separated channels: refgo, slcan, … (default all)", from the trace's own names.
const std::string& channels_description() {
  static const std::string text = [] {
    std::string s = "comma-separated channels: ";
    for (std::size_t i = 0; i < trace::k_channel_count; ++i) {
      if (i > 0) s += ", ";
      s += trace::to_string(static_cast<trace::Channel>(i));
    }
    return s + " (default all)";
  }();
  return text;
}

const std::vector<QueryParam> k_trace_query{
    {"since", "integer", "first sequence number wanted (default 0)"},
    {"channels", "string", channels_description()},
    {"limit", "integer", "at most this many events, 1 … 10000 (default 500)"},

    {"excludePolling", "integer", "1: leave out the requests the pages repeat on a timer (header X-Mcemu-Poll)"}};
const std::vector<QueryParam> k_export_query{
    {"since", "integer", "first sequence number wanted (default 0)"},
    {"limit", "integer", "at most this many events are examined, 1 … 10000 (default 10000)"},
    {"conn", "integer", "only the events of this connection"}};

}  // namespace

const std::vector<Router::Route>& Router::routes() {
  using M = Method;
  static const std::vector<Route> rows{
      {{M::get, "/api/v1/info", "Emulator and drive identity, ports, scripting and clock (web.md §8.1)"},
       &Router::get_info},
      {{M::get, "/api/v1/status", "Status snapshot with the footer strings (web.md §8.2)"}, &Router::get_status},
      {{M::get, "/api/v1/objects", "Every entry of the model's dictionary (web.md §8.3)"}, &Router::get_objects},
      {{M::get,
        "/api/v1/objects/{index}/{sub}",
        "One dictionary entry",
        {},
        "",
        "",
        "application/json",
        {k_400, k_404, k_409}},
       &Router::get_object},
      {{M::put,
        "/api/v1/objects/{index}/{sub}",
        "Write one entry through the OD (origin web)",
        {},
        "application/json",
        k_value_body,
        "application/json",
        {{400, "malformed request (syntax), or a number outside the entry's data type (range)"}, k_404, k_409}},
       &Router::put_object},
      {{M::post,
        "/api/v1/objects/read",
        "Read several entries in one loop iteration",
        {},
        "application/json",
        k_read_body,
        "application/json",
        {k_400, k_415}},
       &Router::post_objects_read},
      {{M::post,
        "/api/v1/refgo",
        "Execute one RefGo line through the built-in interpreter (web.md §8.4)",
        {},
        "application/json",
        k_refgo_body,
        "application/json",
        {k_400, k_415, k_503}},
       &Router::post_refgo},
      {{M::get, "/api/v1/io", "Effective, physical and virtual inputs and the outputs (web.md §8.5)"}, &Router::get_io},
      {{M::put,
        "/api/v1/io/physical-inputs",
        "Set the wire levels of the inputs (simulation API)",
        {},
        "application/json",
        k_inputs_body,
        "application/json",
        {k_400, {409, "an input without a pin on the model"}}},
       &Router::put_physical_inputs},
      {{M::get, "/api/v1/trace", "Trace events (web.md §8.6)", k_trace_query, "", "", "application/json", {k_400}},
       &Router::get_trace},
      {{M::get,
        "/api/v1/trace/candump",
        "CAN frames of the slcan channel as a candump -l log",
        k_export_query,
        "",
        "",
        "text/plain",
        {k_400}},
       &Router::get_trace_candump},
      {{M::get,
        "/api/v1/trace/text",
        "Trace events as timestamped text (default channels refgo,udp)",
        {{"since", "integer", "first sequence number wanted (default 0)"},
         {"channels", "string", "comma-separated channels (default refgo,udp)"},
         {"limit", "integer", "at most this many events, 1 … 10000 (default 10000)"},
         {"conn", "integer", "only the events of this connection"},
         {"excludePolling", "integer", "1: leave out the requests the pages repeat on a timer (header X-Mcemu-Poll)"}},
        "",
        "",
        "text/plain",
        {k_400}},
       &Router::get_trace_text},
      {{M::get,
        "/api/v1/scope",
        "Scope samples every 5 ms of drive time (web.md §8.7)",
        {{"sinceMs", "integer", "drive time of the first sample wanted (default: the whole 60 s ring)"}},
        "",
        "",
        "application/json",
        {k_400}},
       &Router::get_scope},
      {{M::get,
        "/api/v1/led",
        "LED state and Morse schedule (morse-led.md §6.2); a FAULHABER drive: its status LED",
        {{"fromMs", "integer", "with toMs: also the exact green edges in [fromMs, toMs] (≤ 600 000 ms)"},
         {"toMs", "integer", "end of the greenEdges window"}},
        "",
        "",
        "application/json",
        {k_400, k_503}},
       &Router::get_led},
      {{M::get,
        "/api/v1/udp",
        "UDP debug console: listeners, backlog, counters, last messages (udp-debug.md §6)",
        {},
        "",
        "",
        "application/json",
        {k_503}},
       &Router::get_udp},
      {{M::get, "/api/v1/script", "The loaded script (web.md §8.7)", {}, "", "", "application/json", {k_503_engine}},
       &Router::get_script},
      {{M::put,
        "/api/v1/script",
        "Upload a script (raw body)",
        {},
        "text/x-python",
        "",
        "application/json",
        {k_400, {413, "script larger than 65536 bytes"}, k_503_engine}},
       &Router::put_script},
      {{M::post,
        "/api/v1/script/start",
        "Start or restart the script (codeAct 3)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_415, {503, "no script engine, or python3 unavailable (the start still sends its UDP lines)"}}},
       &Router::post_script_start},
      {{M::post,
        "/api/v1/script/stop",
        "Stop the script (codeAct 4)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_415, k_503_engine}},
       &Router::post_script_stop},
      {{M::post,
        "/api/v1/script/pause",
        "Pause the script (codeAct 1)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_415, k_503_engine}},
       &Router::post_script_pause},
      {{M::post,
        "/api/v1/script/resume",
        "Resume the script (codeAct 2)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_415, k_503_engine}},
       &Router::post_script_resume},
      {{M::put,
        "/api/v1/script/autostart",
        "Autostart on/off (3500h.04)",
        {},
        "application/json",
        k_autostart_body,
        "application/json",
        {k_400, k_503_engine}},
       &Router::put_script_autostart},
      {{M::post,
        "/api/v1/store",
        "Store Permanently: 1010h.01 := \"save\" (web.md §7.1)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_409, k_415}},
       &Router::post_store},
      {{M::post,
        "/api/v1/factory-reset",
        "Factory Reset: 1011h.01 := \"load\" (web.md §7.2)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_409, k_415}},
       &Router::post_factory_reset},
      {{M::post,
        "/api/v1/power-cycle",
        "Power loss and power-up in the running process (web.md §8.8)",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_415, k_503},
        true},
       &Router::post_power_cycle},
      {{M::get, "/api/v1/settings", "Runtime settings (web.md §8.9)"}, &Router::get_settings},
      {{M::put,
        "/api/v1/settings",
        "Change runtime settings (any subset)",
        {},
        "application/json",
        k_settings_body,
        "application/json",
        {k_400,
         {403, "would relax the script settings beyond their start values (scriptStrict false, more scriptMemoryMiB)"}},
        true},
       &Router::put_settings},
      {{M::get, "/api/v1/clock", "Clock mode, scale and drive time (web.md §8.10)"}, &Router::get_clock},
      {{M::post,
        "/api/v1/clock/advance",
        "Run n steps of 1 ms (--clock manual only)",
        {},
        "application/json",
        k_advance_body,
        "application/json",
        {k_400, {409, "clock not in manual mode"}, k_415, k_503},
        true},
       &Router::post_clock_advance},
      {{M::get, "/api/v1/faults", "Active fault injections (web.md §9)"}, &Router::get_faults},
      {{M::post,
        "/api/v1/faults",
        "Create a fault injection",
        {},
        "application/json",
        k_fault_body,
        "application/json",
        {k_201, k_400, {409, "refused in the current state (script.kill: no script running)"}, k_415, k_503},
        true},
       &Router::post_faults},
      {{M::del, "/api/v1/faults", "Remove every fault injection", {}, "", "", "application/json", {}, true},
       &Router::delete_faults},
      {{M::del,
        "/api/v1/faults/{id}",
        "Remove one fault injection",
        {},
        "",
        "",
        "application/json",
        {{404, "no active injection with that id"}},
        true},
       &Router::delete_fault},
      {{M::get, "/api/v1/lint", "Master lint: mode, counts per rule, recent findings (docs/lint.md §5)"},
       &Router::get_lint},
      {{M::del, "/api/v1/lint", "Master lint: reset the counts and findings", {}, "", "", "application/json", {}, true},
       &Router::delete_lint},
      {{M::get,
        "/api/v1/faulhaber/programs",
        "MC BASIC: the eight program slots (faulhaber.md §9.1)",
        {},
        "",
        "",
        "application/json",
        {{404, "no MC BASIC on this drive"}}},
       &Router::get_programs},
      {{M::get,
        "/api/v1/faulhaber/programs/{n}",
        "MC BASIC: one slot with its source text",
        {},
        "",
        "",
        "application/json",
        {k_400, {404, "no MC BASIC on this drive"}}},
       &Router::get_program},
      {{M::put,
        "/api/v1/faulhaber/programs/{n}",
        "MC BASIC: store a program text in slot n (1 … 8); a load error is answered 200 with its state",
        {},
        "text/plain",
        "",
        "application/json",
        {k_400, {404, "no MC BASIC on this drive"}, {413, "program larger than 4096 bytes"}}},
       &Router::put_program},
      {{M::post,
        "/api/v1/faulhaber/programs/{n}/start",
        "MC BASIC: start program n",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {k_400, {404, "no MC BASIC on this drive"}, {409, "the slot is empty or has an error"}, k_415}},
       &Router::post_program_start},
      {{M::post,
        "/api/v1/faulhaber/stop",
        "MC BASIC: stop the running program",
        {},
        "application/json",
        k_empty_body,
        "application/json",
        {{404, "no MC BASIC on this drive"}, k_415}},
       &Router::post_basic_stop},
      {{M::put,
        "/api/v1/faulhaber/autostart",
        "MC BASIC: the program started after power on and reset node (0 = none)",
        {},
        "application/json",
        k_autostart_program_body,
        "application/json",
        {k_400, {404, "no MC BASIC on this drive"}}},
       &Router::put_basic_autostart},
      {{M::put,
        "/api/v1/faulhaber/inputs",
        "FAULHABER: physical input levels, bit 0 = DigIn1 (simulation API)",
        {},
        "application/json",
        k_levels_body,
        "application/json",
        {k_400, {404, "not a FAULHABER drive"}}},
       &Router::put_faulhaber_inputs},
      {{M::get, "/api/v1/eds", "CANopen EDS of the model (as mcemu --dump-eds)", {}, "", "", "text/plain", {k_503}},
       &Router::get_eds},
      {{M::get, "/api/v1/openapi.json", "This document"}, &Router::get_openapi},
      {{M::get,
        "/api/v1/ws",
        "WebSocket (web.md §10); a request that is not an upgrade gets 426",
        {},
        "",
        "",
        "application/json",
        {{426, "not a WebSocket upgrade"}}},
       &Router::get_ws},
  };
  return rows;
}

std::vector<RouteDoc> Router::route_docs() {
  std::vector<RouteDoc> out;
  for (const auto& r : routes()) out.push_back(r.doc);
  return out;
}

json Router::openapi() const {
  const auto docs = route_docs();
  return openapi_document(docs, services_.info ? services_.info().version : std::string());
}

Router::Router(device::Device& device, Services services) : device_(device), services_(std::move(services)) {}

Router::~Router() { alive_.end(); }

void Router::journal_text(std::uint64_t conn, const std::string& peer, const std::string& text) {
  if (services_.trace) services_.trace->record(trace::Channel::api, trace::Dir::event, text, conn, peer);
  if (device_.settings().udp_emulator_notes && services_.note) services_.note("api " + text);
}

void Router::journal(const Request& request, const std::string& text) {
  journal_text(request.conn, request.peer, text);
}

void Router::handle(const Request& request, const Respond& respond) {
  // A handler that throws (it must not) still gets exactly one answer: 500, once.
  auto answered = std::make_shared<bool>(false);
  const Respond once = [answered, respond](Response r) {
    if (*answered) return;
    *answered = true;
    respond(std::move(r));
  };
  try {
    dispatch(request, once);
  } catch (const std::exception& e) {
    once(error_json(500, "internal", e.what()));
  }
}

PageContext Router::page_context() {
  PageContext ctx;
  ctx.info = info_json();
  ctx.status = json::parse(status_text());
  const auto& plant = device_.core().plant_params();
  ctx.model.linear = plant.kind == model::Kind::linear;
  ctx.model.input_pins = device_.preset().input_pins;
  ctx.model.output_pins = device_.preset().output_pins;
  ctx.model.temperature_available = plant.temperature_available;
  ctx.model.supply_nominal_v = plant.supply_nominal_v;
  ctx.model.supply_uv_v = plant.supply_uv_v;
  ctx.model.supply_ov_v = plant.supply_ov_v;
  ctx.model.rotary_accel_unit_num = device_.preset().plant.rotary_accel_unit_num;
  ctx.model.rotary_accel_unit_den = device_.preset().plant.rotary_accel_unit_den;
  ctx.object = [this](std::uint16_t index, std::uint8_t sub) -> std::optional<json> {
    const auto v = device_.od().read(index, sub);
    if (!v) return std::nullopt;
    return value_json(*v);
  };
  if (services_.script) ctx.script = services_.script->view();
  return ctx;
}

void Router::page(const Request& request, const Respond& answer) {
  // The template is filled when the answer is sent (a hook may answer later, after its action).
  const Respond respond = [this, alive = alive_.watch(), answer](Response r) {
    if (alive && r.content_type.rfind("text/html", 0) == 0 && r.body.find("{{") != std::string::npos) {
      r.body = render_page(r.body, page_context(), embedded_partials());
    }
    answer(std::move(r));
  };
  const std::string path(target_path(request.target));
  if (const auto status = device_.faults().transport().take_http_error(path)) {
    Response r;
    r.status = *status;
    r.content_type = "text/html; charset=utf-8";
    r.body = "<!DOCTYPE html><html><head><title>" + std::to_string(*status) + "</title></head><body><h1>" +
             std::to_string(*status) + "</h1><p>Injected by mcemu fault injection (http.error).</p></body></html>\n";
    r.headers.emplace_back("Cache-Control", "no-store");
    return respond(std::move(r));
  }
  if (!device_.personality().drive_pages) {
    const bool read = request.method == "GET" || request.method == "HEAD";
    if (path == "/emulator.html") {
      Request tmpl = request;
      tmpl.target = std::string(k_fh_emulator_template);
      if (auto asset = serve_asset(tmpl)) return respond(std::move(*asset));
    }
    if (read && (is_movingcap_page(path) || path == k_fh_emulator_template)) {
      return respond(redirect_to("/emulator.html"));
    }
    if (is_movingcap_page(path)) return respond(not_found_page());  // POST /program.html: no such endpoint
  } else if (path == k_fh_emulator_template) {
    return respond(not_found_page());
  }
  if (path == "/program.html") return program_page(request, respond);  // web.md §6 (handlers_script.cpp)
  if (services_.pages && services_.pages(request, respond)) return;
  if (auto asset = serve_asset(request)) return respond(std::move(*asset));  // web/ui/, embedded
  respond(not_found_page());
}

void Router::dispatch(const Request& request, const Respond& respond) {
  const std::string path(target_path(request.target));
  if (path.rfind("/api/", 0) != 0) return page(request, respond);

  // The routes of the path: a literal pattern equal to it (most requests: status, info, trace; looked
  // up, built once), else those of the matching patterns with the fewest parameters (a literal
  // segment beats a parameter).
  static const auto literal = [] {
    std::unordered_map<std::string_view, std::vector<const Route*>> m;
    for (const auto& r : routes()) {
      if (parameter_count(r.doc.path) == 0) m[r.doc.path].push_back(&r);
    }
    return m;
  }();
  std::vector<const Route*> matched;
  const std::vector<const Route*>* candidates = nullptr;
  if (const auto it = literal.find(path); it != literal.end()) {
    candidates = &it->second;
  } else {
    std::size_t best = SIZE_MAX;
    for (const auto& r : routes()) {
      if (path_matches(r.doc.path, path)) best = std::min(best, parameter_count(r.doc.path));
    }
    // An API client parses JSON, also when it asked for a path that does not exist (web.md §1.4).
    if (best == SIZE_MAX) return respond(unknown_api_path(path));
    for (const auto& r : routes()) {
      if (parameter_count(r.doc.path) == best && path_matches(r.doc.path, path)) matched.push_back(&r);
    }
    candidates = &matched;
  }
  const auto method = method_of(request.method);
  const Route* route = nullptr;
  std::string allow;
  for (const Route* r : *candidates) {
    if (!allow.empty()) allow += ", ";
    allow += to_string(r->doc.method);
    if (r->doc.method == Method::get) allow += ", HEAD";
    if (method && r->doc.method == *method) route = r;
  }
  if (!route) {
    auto r = error_json(405, "method", "method " + request.method + " not allowed on " + path);
    r.headers.emplace_back("Allow", allow);
    return respond(std::move(r));
  }
  // docs/security.md: with --api-token, mcemu's own emulator endpoints need the bearer token; the
  // drive's own pages and endpoints stay as open as on the real drive.
  if (route->doc.token && !services_.api_token.empty() &&
      !bearer_matches(request.header("authorization"), services_.api_token)) {
    auto r =
        error_json(401, "unauthorized",
                   "this emulator endpoint needs the bearer token of mcemu's --api-token (Authorization: Bearer …)");
    r.headers.emplace_back("WWW-Authenticate", "Bearer realm=\"mcemu\"");
    return respond(std::move(r));
  }
  if (request.method == "POST" && !is_json_media_type(request.content_type)) {
    return respond(error_json(415, "content-type", "POST requests to /api/ need Content-Type: application/json"));
  }
  auto query = parse_query(request.target);
  if (!query) return respond(error_json(400, "syntax", "malformed query string"));
  for (const auto& param : *query) {
    const std::string& key = param.first;  // not a structured binding: clang 14 cannot capture those
    const auto& allowed = route->doc.query;
    if (std::none_of(allowed.begin(), allowed.end(), [&](const QueryParam& q) { return q.name == key; })) {
      return respond(error_json(400, "syntax", "unknown query parameter \"" + key + "\""));
    }
  }
  const Ctx ctx{request, *match_path(route->doc.path, path), std::move(*query), respond};
  (this->*route->handler)(ctx);
}

ClockInfo Router::clock_info() const { return services_.clock ? services_.clock() : ClockInfo{}; }

StatusInputs Router::status_inputs() const {
  StatusInputs in{device_.od()};
  in.time_ms = device_.core().time_ms();
  in.state = device_.core().state();
  in.velocity_inc_s = device_.core().actual_velocity_inc_s();
  in.temperature_available = device_.core().plant_params().temperature_available;
  in.input_count = static_cast<int>(device_.preset().input_pins.size());
  in.output_count = static_cast<int>(device_.preset().output_pins.size());
  if (device_.personality().faulhaber) {
    FaulhaberStatus fh;
    if (const auto* programs = device_.basic()) {
      fh.basic_running = programs->running();
      fh.basic_line = programs->running_line();
      fh.basic_autostart = programs->autostart();
    }
    if (in.temperature_available) fh.temperature_c = std::llround(device_.core().temperature_c());
    in.faulhaber = fh;
    return in;
  }
  if (services_.script) {
    in.python = services_.script->status();
    in.refgo.attach_mode = services_.script->refgo_attach_mode();
  }
  in.refgo.clients = services_.refgo_clients ? services_.refgo_clients() : 0;
  if (const auto* refgo = device_.refgo()) {
    const auto& vars = refgo->variables();
    in.refgo.repeat_way = vars.repeat_way;
    in.refgo.wait_time_ms = vars.wait_time_ms;
    in.refgo.back_and_forth = refgo->programs().back_and_forth_active();
    if (const auto due = refgo->programs().jog_stop_due_ms()) {
      in.refgo.jog_timer_ms = *due > in.time_ms ? *due - in.time_ms : 0;
    }
  }
  in.udp_listeners = services_.udp_listeners ? services_.udp_listeners() : 0;
  if (services_.led_state) in.led = services_.led_state();
  return in;
}

std::string Router::status_text() { return snapshots_.build(status_inputs()); }

std::string Router::status_message() {
  std::string text = status_text();  // "{…}": an object, never empty
  return R"({"type":"status",)" + text.substr(1);
}

Response error_page(int status, const std::string& reason) {
  Response r;
  r.status = status;
  r.body = dump_json(json{{"error", {{"code", "http"}, {"message", reason}}}});
  r.headers.emplace_back("Cache-Control", "no-store");
  return r;
}

}  // namespace mcemu::web::api
