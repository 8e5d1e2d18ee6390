// Router handlers of the script engine: the JSON script endpoints (web.md §8.7) and the real
// drive's /program.html, which Fullmo's uploader and the Code page use (web.md §6): the multipart
// upload (§6.1) and GET ?codeAct=N (§6.2), both behind the cross-site check of §1.3.
#include <charconv>

#include "drive/od/objects.hpp"
#include "web/api/http_util.hpp"
#include "web/api/multipart.hpp"
#include "web/api/origin.hpp"
#include "web/api/router.hpp"
#include "web/assets/assets.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

constexpr std::size_t k_max_script_bytes = 65536;  // web.md §6.1
// The file input's name, exact and case-sensitive (web.md §6.1; Fullmo's uploader sends it).
constexpr std::string_view k_upload_field = "Python script file for MovingCap CODE";
const char* const k_no_engine = "script engine not available in this version";

Response bad(const std::string& message) { return error_json(400, "syntax", message); }
Response unavailable(const std::string& what) { return error_json(503, "unavailable", what); }

std::string html_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// The Code page of web.md §5.7 as plain HTML, used while the web UI has no /program.html of its
// own: the same element ids, the upload form with the exact field name, the buttons as links to
// ?codeAct=N, the Script Viewer and the Execution Status.
std::string plain_code_page(const ScriptView& v, std::string_view error) {
  const auto button = [](const char* id, int act, const std::string& label) {
    return "<a id=\"" + std::string(id) + "\" href=\"/program.html?codeAct=" + std::to_string(act) + "\">" + label +
           "</a>";
  };
  std::string page =
      "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>MovingCap CODE</title></head><body>\n"
      "<h1>Code (Python)</h1>\n";
  if (!error.empty()) page += "<p id=\"code-error\" role=\"alert\">" + html_escape(error) + "</p>\n";
  page += "<h2>Script Startup</h2>\n<p>Autostart - Automatic start after voltage reset " +
          button("code-auto-on", 5, v.autostart ? "ON [X]" : "ON") + " " +
          button("code-auto-off", 6, v.autostart ? "OFF" : "OFF [X]") + "</p>\n";
  page +=
      "<h2>Upload New Script</h2>\n"
      "<form method=\"post\" action=\"/program.html\" enctype=\"multipart/form-data\">"
      "<input id=\"code-file\" type=\"file\" name=\"" +
      std::string(k_upload_field) + "\" accept=\".py\"> <button id=\"code-upload\" type=\"submit\">Upload</button> " +
      button("code-run", 3, "RUN") + "</form>\n<p>Please select *.py script file to upload</p>\n";
  page += "<h2>Python Script Viewer</h2>\n<pre id=\"code-viewer\">" + html_escape(v.source) + "</pre>\n";
  page += "<h2>MovingCap CODE / Master Program - MicroPython Script Engine</h2>\n<p>" +
          button("code-pause", 1, "Pause/Break") + " " + button("code-resume", 2, "Resume") + " " +
          button("code-stop", 4, "Stop") + " " + button("code-restart", 3, "Restart") + "</p>\n";
  page += "<p>Execution Status <span id=\"code-status\">" + html_escape(v.state + " " + v.id) + "</span></p>\n";
  page += "</body></html>\n";
  return page;
}

// Where the embedded Code page wants an upload's refusal: in its upload section, under the
// controls it concerns (not above the menu bar).
constexpr std::string_view k_error_marker = "<!--code-error-->";

// The embedded page with an error note at its marker; a page without one gets it at the start of
// its <main> (the page's content), failing that right after <body>.
std::string with_error(std::string page, std::string_view error) {
  if (error.empty()) return page;
  const std::string note = "<p id=\"code-error\" class=\"notice error\" role=\"alert\">" + html_escape(error) + "</p>";
  if (const auto at = page.find(k_error_marker); at != std::string::npos) {
    page.replace(at, k_error_marker.size(), note);
    return page;
  }
  for (const char* tag : {"<main", "<body"}) {
    const auto open = page.find(tag);
    const auto end = open == std::string::npos ? std::string::npos : page.find('>', open);
    if (end == std::string::npos) continue;
    page.insert(end + 1, note);
    return page;
  }
  return note + page;
}

}  // namespace

// ---- JSON (web.md §8.7) -----------------------------------------------------------------------

json Router::script_json(const ScriptView& v) const {
  return json{{"id", v.id},         {"state", v.state},           {"autostart", v.autostart},
              {"length", v.length}, {"crc32", hex_u32(v.crc32)},  {"line", v.line},
              {"source", v.source}, {"hasPrivate", v.has_private}};
}

void Router::get_script(const Ctx& c) {
  if (!services_.script) return c.respond(unavailable(k_no_engine));
  c.respond(json_response(200, script_json(services_.script->view())));
}

void Router::put_script(const Ctx& c) {
  if (!services_.script) return c.respond(unavailable(k_no_engine));
  if (c.req.body.empty()) return c.respond(bad("empty script"));
  if (c.req.body.size() > k_max_script_bytes) {
    return c.respond(error_json(413, "too-large", "script larger than 65536 bytes"));
  }
  if (auto error = services_.script->upload(c.req.body)) return c.respond(bad(*error));
  journal(c.req, "script upload, " + std::to_string(c.req.body.size()) + " bytes");
  c.respond(json_response(200, script_json(services_.script->view())));
}

void Router::script_action(const Ctx& c, const char* name, void (ScriptControl::*action)()) {
  if (!services_.script) return c.respond(unavailable(k_no_engine));
  if (!empty_body(c)) return;
  (services_.script->*action)();
  journal(c.req, std::string("script ") + name);
  // scripting.md §10.1.8: the start was made (its UDP lines say so) but no engine can run it.
  if (action == &ScriptControl::start && !services_.script->available()) {
    return c.respond(unavailable("script engine unavailable: " + services_.script->engine()));
  }
  c.respond(json_response(200, script_json(services_.script->view())));
}

void Router::post_script_start(const Ctx& c) { script_action(c, "start", &ScriptControl::start); }
void Router::post_script_stop(const Ctx& c) { script_action(c, "stop", &ScriptControl::stop); }
void Router::post_script_pause(const Ctx& c) { script_action(c, "pause", &ScriptControl::pause); }
void Router::post_script_resume(const Ctx& c) { script_action(c, "resume", &ScriptControl::resume); }

void Router::put_script_autostart(const Ctx& c) {
  if (!services_.script) return c.respond(unavailable(k_no_engine));
  const auto body = json_object_body(c.req);
  if (!body || body->size() != 1 || !body->contains("on") || !(*body)["on"].is_boolean()) {
    return c.respond(bad("expected {\"on\": true|false}"));
  }
  const bool on = (*body)["on"].get<bool>();
  const auto code =
      device_.od().write(od::k_script, od::k_script_autostart, od::Value{std::int64_t{on ? 1 : 0}}, od::Origin::web);
  journal(c.req, std::string("script autostart ") + (on ? "on" : "off"));
  if (code != od::AbortCode::none) return c.respond(abort_response(code));
  c.respond(json_response(200, script_json(services_.script->view())));
}

// ---- /program.html (web.md §6) ----------------------------------------------------------------

Response Router::code_page(int status, std::string_view error) const {
  Response r;
  r.status = status;
  r.content_type = "text/html; charset=utf-8";
  r.headers.emplace_back("Cache-Control", "no-store");
  if (const auto* asset = assets::find("/program.html")) {
    r.content_type = std::string(asset->mime);
    r.body = with_error(std::string(asset->bytes), error);
  } else {
    ScriptView none;
    none.id = "(empty)";
    none.state = "OFF";
    r.body = plain_code_page(services_.script ? services_.script->view() : none, error);
  }
  return r;
}

// GET (and HEAD) answer the Code page; GET ?codeAct=N performs the action first (§6.2: any
// other value, or a non-numeric one, is ignored). HEAD never acts (§1.4).
void Router::program_page(const Request& request, const Respond& respond) {
  if (request.method == "POST") return program_upload(request, respond);
  if (request.method != "GET" && request.method != "HEAD") {
    Response r = code_page(405, "method " + request.method + " not allowed on /program.html");
    r.headers.emplace_back("Allow", "GET, HEAD, POST");
    return respond(std::move(r));
  }
  std::optional<std::string> act;
  if (const auto query = parse_query(request.target)) {
    if (const auto it = query->find("codeAct"); it != query->end()) act = it->second;
  }
  if (request.method == "GET" && act) {
    if (is_cross_site(request)) return respond(cross_site_refused());
    if (!services_.script) return respond(code_page(503, k_no_engine));
    int n = 0;
    const std::string& text = *act;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
    if (!text.empty() && ec == std::errc() && ptr == text.data() + text.size()) {
      services_.script->code_act(n);
      journal(request, "codeAct=" + std::to_string(n));
    }
  }
  respond(code_page(200, ""));
}

// §6.1: the part named exactly k_upload_field of a multipart/form-data body, 1 … 65 536 bytes.
void Router::program_upload(const Request& request, const Respond& respond) {
  if (is_cross_site(request)) return respond(cross_site_refused());
  if (!services_.script) return respond(code_page(503, k_no_engine));
  const auto boundary = multipart_boundary(request.content_type);
  if (!boundary) return respond(code_page(400, "upload refused: the request is not multipart/form-data"));
  const auto parts = parse_multipart(request.body, *boundary);
  if (!parts) return respond(code_page(400, "upload refused: malformed multipart/form-data body"));
  const FormPart* file = nullptr;
  for (const auto& p : *parts) {
    if (p.name == k_upload_field) {
      file = &p;
      break;
    }
  }
  if (!file) return respond(code_page(400, "upload refused: no file field \"" + std::string(k_upload_field) + "\""));
  if (file->content.empty()) return respond(code_page(400, "upload refused: the script file is empty"));
  if (file->content.size() > k_max_script_bytes) {
    return respond(code_page(413, "upload refused: the script is larger than 65536 bytes"));
  }
  if (auto error = services_.script->upload(file->content)) return respond(code_page(400, *error));
  journal(request, "script upload (program.html), " + std::to_string(file->content.size()) + " bytes");
  respond(code_page(200, ""));
}

}  // namespace mcemu::web::api
