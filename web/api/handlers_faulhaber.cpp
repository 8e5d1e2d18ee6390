// Router handlers of the FAULHABER drive's own endpoints (faulhaber.md §9.1): MC BASIC program slots,
// start/stop, autostart and the physical input levels for tests. On a drive without MC BASIC (a
// MovingCap) they answer 404 like an unknown path.
#include "web/api/http_util.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api {

using nlohmann::json;

namespace {

constexpr std::size_t k_max_program_bytes = 4096;  // faulhaber.md §9.1

Response bad(const std::string& message) { return error_json(400, "syntax", message); }
Response no_basic() { return error_json(404, "not-found", "this drive has no MC BASIC (a FAULHABER model has)"); }

std::optional<int> slot_of(const std::string& text) {
  if (text.size() != 1 || text[0] < '1' || text[0] > '8') return std::nullopt;
  return text[0] - '0';
}

}  // namespace

json Router::program_json(int slot) const {
  const auto* programs = device_.basic();
  const auto st = programs->status(slot);
  json j{{"slot", slot}, {"state", std::string(basic::to_string(st.state))}, {"bytes", st.bytes}};
  if (st.state == basic::SlotState::error) {
    j["line"] = st.line;
    j["message"] = st.message;
    if (st.code != od::AbortCode::none) j["abortCode"] = abort_hex(st.code);
  }
  if (st.state == basic::SlotState::running) {
    if (const auto line = programs->running_line()) j["runningLine"] = *line;
  }
  return j;
}

json Router::programs_json() const {
  const auto* programs = device_.basic();
  json list = json::array();
  for (int slot = 1; slot <= basic::Programs::k_slots; ++slot) list.push_back(program_json(slot));
  return json{{"programs", list},
              {"running", programs->running()},
              {"autostart", programs->autostart()},
              {"saves", device_.basic_saves()}};
}

void Router::get_programs(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  c.respond(json_response(200, programs_json()));
}

void Router::get_program(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  const auto slot = slot_of(c.params[0]);
  if (!slot) return c.respond(bad("program number 1 … 8"));
  json j = program_json(*slot);
  j["source"] = std::string(device_.basic()->source(*slot));
  c.respond(json_response(200, j));
}

// A program with a load error is still stored and answered 200 with its error state (the user sees
// where to fix it); more than 4096 bytes → 413 and nothing is stored (faulhaber.md §9.1).
void Router::put_program(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  const auto slot = slot_of(c.params[0]);
  if (!slot) return c.respond(bad("program number 1 … 8"));
  if (c.req.body.size() > k_max_program_bytes) {
    return c.respond(error_json(413, "too-large", "program larger than 4096 bytes"));
  }
  device_.upload_program(*slot, c.req.body);
  const json state = program_json(*slot);
  journal(c.req, "basic program " + std::to_string(*slot) + " uploaded, " + std::to_string(c.req.body.size()) +
                     " bytes: " + state["state"].get<std::string>());
  c.respond(json_response(200, state));
}

void Router::post_program_start(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  const auto slot = slot_of(c.params[0]);
  if (!slot) return c.respond(bad("program number 1 … 8"));
  if (!empty_body(c)) return;
  if (device_.basic()->start(*slot) != basic::Programs::Start::ok) {
    auto r = json_response(409, program_json(*slot));
    return c.respond(std::move(r));
  }
  journal(c.req, "basic program " + std::to_string(*slot) + " started");
  c.respond(json_response(200, program_json(*slot)));
}

void Router::post_basic_stop(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  if (!empty_body(c)) return;
  device_.basic()->stop();
  journal(c.req, "basic stop");
  c.respond(json_response(200, programs_json()));
}

void Router::put_basic_autostart(const Ctx& c) {
  if (!device_.basic()) return c.respond(no_basic());
  const auto body = json_object_body(c.req);
  const auto slot =
      body && body->size() == 1 && body->contains("program") ? json_uint((*body)["program"], 0, 8) : std::nullopt;
  if (!slot) return c.respond(bad("expected {\"program\": 0 … 8} (0 = none)"));
  device_.set_basic_autostart(static_cast<int>(*slot));
  journal(c.req, "basic autostart " + std::to_string(*slot));
  c.respond(json_response(200, programs_json()));
}

// Physical input levels DigIn1… as a bit mask (bit 0 = DigIn1), for tests (faulhaber.md §9.1).
void Router::put_faulhaber_inputs(const Ctx& c) {
  if (!device_.personality().faulhaber) return c.respond(no_basic());
  const auto body = json_object_body(c.req);
  const auto levels =
      body && body->size() == 1 && body->contains("levels") ? json_uint((*body)["levels"], 0, 0xFF) : std::nullopt;
  if (!levels) return c.respond(bad("expected {\"levels\": 0 … 255} (bit 0 = DigIn1)"));
  device_.core().set_external_input_levels(static_cast<std::uint32_t>(*levels));
  device_.handle_events();
  journal(c.req, "faulhaber inputs " + std::to_string(*levels));
  c.respond(json_response(200, json{{"levels", *levels}}));
}

}  // namespace mcemu::web::api
