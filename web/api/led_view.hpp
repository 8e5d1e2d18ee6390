// The JSON of the two LEDs (morse-led.md §6): the "led" member of the status snapshot (§6.1) and
// GET /api/v1/led with the optional ?fromMs=A&toMs=B window (§6.2). PURE: the router calls these
// with the drive's LEDs and its drive time; nothing here reads a clock.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string_view>

#include "drive/led/leds.hpp"
#include "web/api/http_types.hpp"

namespace mcemu::web::api {

// {"green": true, "yellow": false} at drive time `time_ms` (§6.1).
nlohmann::json led_state_json(const led::Leds& leds, std::uint64_t time_ms);

// The document of §6.2 at drive time `time_ms`; with a window, "greenEdges" for it.
nlohmann::json led_json(const led::Leds& leds, std::uint64_t time_ms);

// GET /api/v1/led. `query` is the part of the target after '?' (empty without one). fromMs and toMs
// are decimal integers, both or neither, with 0 ≤ toMs − fromMs ≤ 600 000; anything else is a 400
// {"error": {"code": "syntax", …}}. Other parameters are ignored.
Response led_response(const led::Leds& leds, std::uint64_t time_ms, std::string_view query);

}  // namespace mcemu::web::api
