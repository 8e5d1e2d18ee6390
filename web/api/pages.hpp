// Server-side rendering of the drive's pages (web.md §3.5): every embedded .html file is a template
// whose placeholders the server fills at request time, so that a client without JavaScript (curl)
// sees the menu bar, the LEDs, the footer strings of §4.2 and the page's current object values. The
// page's script then keeps everything live over the WebSocket.
//
// Template syntax (the whole language):
//   {{> name}}   the partial /static/partials/<name>.html (itself a template; one level deep)
//   {{key}}      a value, HTML-escaped, from the keys below; an unknown key is left as written
//                (tests/web/pages_test.cpp renders every embedded page and finds none)
//
// Keys: info.<path> and status.<path> (a dotted path into GET /api/v1/info and the status snapshot;
// strings as they are, numbers in decimal, null as "-"), footer.<field> (status.footer; footer.live
// is HTML: the `ERR …` part inside an <a href="/index.html" class="err">), led.green / led.yellow
// ("1"/"0"), model.short (1008h before "_ETH", models.md §2), model.accelerationUnit, lastError (§5.1 text or "-"),
// od.IIII.SS (the object's value: decimal or string; "" when it cannot be read), odh.IIII.SS (H4 of
// it), code.status / code.autoOn / code.autoOff / code.viewer / code.engine (the Code page, §5.7),
// page.data (JSON for the page's script: not HTML-escaped, `<`, `>` and `&` as \u escapes so that it
// is safe inside <script type="application/json">).
//
// PURE: everything comes in through PageContext.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "web/api/services.hpp"

namespace mcemu::web::api {

// What the pages need to know about the model beyond /api/v1/info (page.data).
struct PageModel {
  bool linear = false;  // linear models: velocities always in user units/s (drive-core.md §3.5)
  std::vector<int> input_pins;
  std::vector<int> output_pins;
  bool temperature_available = true;
  double supply_nominal_v = 48;
  double supply_uv_v = 18;
  double supply_ov_v = 60;
  // drive-core.md §3.6: rotary 1 unit = num/den motor rev/s²
  std::int64_t rotary_accel_unit_num = 1;
  std::int64_t rotary_accel_unit_den = 36;
};

struct PageContext {
  nlohmann::json info;    // the object of GET /api/v1/info
  nlohmann::json status;  // a status snapshot (web.md §8.2)
  PageModel model;
  // The current value of an object as JSON (integer or string), nullopt when it cannot be read.
  std::function<std::optional<nlohmann::json>(std::uint16_t index, std::uint8_t sub)> object;
  std::optional<ScriptView> script;  // nullopt: no script engine in this version
};

// The text of a partial by name ("header" → /static/partials/header.html), nullopt if there is none.
using PartialLookup = std::function<std::optional<std::string_view>(std::string_view name)>;
// The embedded partials (web/ui/static/partials/).
PartialLookup embedded_partials();

std::string render_page(std::string_view tmpl, const PageContext& ctx, const PartialLookup& partials);

// The keys of `tmpl` (partials expanded) that render_page does not know.
std::vector<std::string> unknown_keys(std::string_view tmpl, const PageContext& ctx, const PartialLookup& partials);

// The accelerations' unit as the Servo page's footnote (*3) states it (drive-core.md §3.6).
std::string acceleration_unit_text(const PageModel& m);
// "MC349" of "MC349_ETH_RE" (models.md §2); the whole name if it has no "_ETH".
std::string short_model_name(std::string_view device_name);
// Text with &, <, >, " and ' replaced by entities.
std::string html_escape(std::string_view text);

}  // namespace mcemu::web::api
