// The master lint's endpoints (docs/lint.md §5): GET /api/v1/lint (mode, totals, every rule with
// its explanation, reference and counts, the recent findings) and DELETE /api/v1/lint (counts and
// findings cleared; an emulator endpoint, --api-token protects it).
#include "lint/json_view.hpp"
#include "web/api/http_util.hpp"
#include "web/api/router.hpp"

namespace mcemu::web::api {

void Router::get_lint(const Ctx& c) {
  Response r = json_response(200, lint::lint_json(device_.lint().engine()));
  r.headers.emplace_back("Cache-Control", "no-store");
  c.respond(std::move(r));
}

void Router::delete_lint(const Ctx& c) {
  device_.lint().engine().reset();
  journal(c.req, "lint reset");
  c.respond(json_response(200, lint::lint_json(device_.lint().engine())));
}

}  // namespace mcemu::web::api
