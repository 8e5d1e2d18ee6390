// The trace ring as the JSON of web.md §8.6 and as two export files:
// - a candump log of the CAN frames of the `slcan` channel, one line per frame in the format
//   `candump -l` writes: "(1700000000.123456) can0 123#DEADBEEF" (RTR: "123#R" or "123#R4";
//   extended identifiers with 8 digits), readable by python-can's can.LogReader;
// - a timestamped text log of any channels (default refgo and udp), one line per event:
//   "<wall> <timeMs> <channel> <dir> <conn> <text>", control bytes shown Docklight-like (<CR>, <LF>).
// PURE: formats events that the caller queried from the ring.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "protocols/can/frame.hpp"
#include "trace/trace.hpp"

namespace mcemu::web::api {

nlohmann::json event_json(const trace::Event& e);
// {"events": […], "nextSeq": n, "dropped": n}
nlohmann::json trace_json(const trace::Ring::Result& r);

// The CAN frame of an SLCAN frame line (t/T/r/R, optional 4-digit timestamp, optional CR), or
// nullopt for any other line (commands, acks, BEL, malformed text).
std::optional<can::Frame> frame_of_slcan_line(std::string_view line);
// "123#DEADBEEF", "12345678#00", "123#R", "123#R4"
std::string candump_frame(const can::Frame& f);

// The candump log of the frames among `events` (other events are skipped). The time of a line is
// the event's wall time; an event without one uses its drive time instead.
std::string candump_log(std::span<const trace::Event> events, std::string_view interface_name = "can0");

// "OR6041,0,h<CR>": CR, LF and TAB as <CR>, <LF>, <TAB>, other control bytes as <XX> (hex).
std::string render_control(std::string_view text);
std::string text_log(std::span<const trace::Event> events);

}  // namespace mcemu::web::api
