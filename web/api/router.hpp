// The HTTP request → response mapping of the web server without any socket (web.md §1.3, §1.4,
// §7, §8, §9). PURE: the Beast adapter in web/net converts to and from these plain values.
//
// Dispatch is by the route table (routes()): one row per method and path pattern, each with its
// handler and its OpenAPI description; GET /api/v1/openapi.json is generated from the same rows.
// A path no row matches gets the 404 page, a method no row of the path has gets 405 with Allow,
// a POST to /api/ without application/json gets 415 (§1.3), a query parameter the row does not
// name gets 400. Paths outside /api/ go to /program.html's handler (the real drive's script upload
// and control endpoint, web.md §6), Services::pages (after the http.error injection), then the
// embedded files; every HTML answer on that path is rendered as a page template (pages.hpp) when it
// is sent, so that a page answered after an action shows the state after it. A drive without the
// MovingCap pages (a FAULHABER MC) answers /emulator.html with its own template /faulhaber.html
// and redirects `/` and the MovingCap pages there (web/README.md "FAULHABER drive").
// No CORS header is ever sent.
//
// Contract: single-threaded (event loop). handle() calls `respond` exactly once, possibly after it
// has returned (a Store answers when the file is durable, a clock advance after its last step).
// The router is not stepped: it reads the drive bundle (device/device.hpp) when asked, and the
// bundle outlives it.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "base/liveness.hpp"
#include "device/device.hpp"
#include "web/api/http_types.hpp"
#include "web/api/pages.hpp"
#include "web/api/routes.hpp"
#include "web/api/services.hpp"
#include "web/api/status.hpp"

namespace mcemu::web::api {

class Router {
 public:
  Router(device::Device& device, Services services);
  ~Router();
  Router(const Router&) = delete;
  Router& operator=(const Router&) = delete;

  void handle(const Request& request, const Respond& respond);

  // A fresh status snapshot (web.md §8.2), seq + 1; the WebSocket hub calls this once per period.
  std::string status_text();
  // The same with "type":"status" first: the WebSocket status message (web.md §10.3).
  std::string status_message();
  // GET /api/v1/info's object (web.md §8.1): the WebSocket hello carries it.
  nlohmann::json info_json() const;
  std::string info_text() const;
  // The inputs of status_text() as they are now (for callers that build the snapshot themselves).
  StatusInputs status_inputs() const;
  // The drive's runtime settings as GET /api/v1/settings shows them (web.md §8.9).
  const device::RuntimeSettings& settings() const { return device_.settings(); }

  // The route table's documentation rows, in table order.
  static std::vector<RouteDoc> route_docs();
  nlohmann::json openapi() const;

  // One request as a handler sees it: the path parameters in pattern order, the decoded query.
  struct Ctx {
    const Request& req;
    std::vector<std::string> params;
    std::map<std::string, std::string> query;
    const Respond& respond;
  };
  using Handler = void (Router::*)(const Ctx&);
  struct Route {
    RouteDoc doc;
    Handler handler;
  };

 private:
  static const std::vector<Route>& routes();
  void dispatch(const Request& request, const Respond& respond);
  void page(const Request& request, const Respond& respond);
  // What the page templates are filled with (web.md §3.5): info, a fresh status snapshot, objects.
  PageContext page_context();
  // API write journal: trace channel api (web.md §8.6) and, with udpEmulatorNotes, a UDP note.
  void journal(const Request& request, const std::string& text);
  void journal_text(std::uint64_t conn, const std::string& peer, const std::string& text);

  // handlers_drive.cpp
  void get_info(const Ctx& c);
  void get_status(const Ctx& c);
  void get_objects(const Ctx& c);
  void get_object(const Ctx& c);
  void put_object(const Ctx& c);
  void post_objects_read(const Ctx& c);
  void post_refgo(const Ctx& c);
  void get_io(const Ctx& c);
  void put_physical_inputs(const Ctx& c);
  void post_store(const Ctx& c);
  void post_factory_reset(const Ctx& c);
  void post_power_cycle(const Ctx& c);
  void get_eds(const Ctx& c);
  void get_openapi(const Ctx& c);
  void get_ws(const Ctx& c);
  void store_or_reset(const Ctx& c, bool store);
  // True for a body {} (or an empty POST body); otherwise answers 400 and returns false.
  bool empty_body(const Ctx& c);
  // handlers_emulator.cpp
  void get_trace(const Ctx& c);
  void get_trace_candump(const Ctx& c);
  void get_trace_text(const Ctx& c);
  void get_scope(const Ctx& c);
  void get_led(const Ctx& c);
  void get_udp(const Ctx& c);
  // handlers_script.cpp: the JSON script endpoints (web.md §8.7) and /program.html (§6)
  void get_script(const Ctx& c);
  void put_script(const Ctx& c);
  void post_script_start(const Ctx& c);
  void post_script_stop(const Ctx& c);
  void post_script_pause(const Ctx& c);
  void post_script_resume(const Ctx& c);
  void put_script_autostart(const Ctx& c);
  void program_page(const Request& request, const Respond& respond);
  void program_upload(const Request& request, const Respond& respond);
  Response code_page(int status, std::string_view error) const;
  // handlers_faulhaber.cpp: MC BASIC programs and input levels (faulhaber.md §9.1)
  void get_programs(const Ctx& c);
  void get_program(const Ctx& c);
  void put_program(const Ctx& c);
  void post_program_start(const Ctx& c);
  void post_basic_stop(const Ctx& c);
  void put_basic_autostart(const Ctx& c);
  void put_faulhaber_inputs(const Ctx& c);
  nlohmann::json program_json(int slot) const;
  nlohmann::json programs_json() const;
  void get_settings(const Ctx& c);
  void put_settings(const Ctx& c);
  void get_clock(const Ctx& c);
  void post_clock_advance(const Ctx& c);
  void get_faults(const Ctx& c);
  void post_faults(const Ctx& c);
  void delete_faults(const Ctx& c);
  void delete_fault(const Ctx& c);
  // handlers_lint.cpp (docs/lint.md §5)
  void get_lint(const Ctx& c);
  void delete_lint(const Ctx& c);
  void script_action(const Ctx& c, const char* name, void (ScriptControl::*action)());
  nlohmann::json io_json() const;
  nlohmann::json script_json(const ScriptView& v) const;
  ClockInfo clock_info() const;

  device::Device& device_;
  Services services_;
  StatusSnapshots snapshots_;
  base::LivenessToken alive_;  // late completions check this is still alive
};

// The bodies of the error responses the adapter produces itself (431, 413, 400).
Response error_page(int status, const std::string& reason);

}  // namespace mcemu::web::api
