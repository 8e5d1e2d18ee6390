// Fuzz target: the SLCAN line codec (slcan-canopen.md §3.4–§3.6). Input: one line (without its
// terminator). Oracles: parse_line() never throws; a parsed frame is valid (DLC ≤ 8, identifier in
// range, no data in a remote frame) and encode_frame() of it parses back to the same frame and
// has exactly 2·DLC data digits; the encoder never emits lower-case hex, LF or BEL.
#include <string>

#include "protocols/slcan/codec.hpp"
#include "tests/fuzz/drive_bundle.hpp"

using namespace mcemu;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const auto r = slcan::parse_line(line);
  const auto* c = std::get_if<slcan::Command>(&r);
  if (!c) {
    (void)slcan::to_string(std::get<slcan::ParseError>(r));
    return 0;
  }
  if (c->kind != slcan::CommandKind::frame) return 0;
  const can::Frame& f = c->frame;
  if (f.dlc > 8) fuzz::fail("DLC above 8");
  if (f.id > (f.extended ? 0x1FFFFFFFu : 0x7FFu)) fuzz::fail("identifier out of range");
  for (const bool stamp : {false, true}) {
    const std::string out =
        slcan::encode_frame(f, stamp ? std::optional(std::chrono::milliseconds(size * 977)) : std::nullopt);
    if (out.empty() || out.back() != '\r') fuzz::fail("encoded frame without CR");
    if (out.find_first_of("\n\aabcdef") != std::string::npos) fuzz::fail("encoded frame with LF, BEL or lower case");
    const std::size_t head = (f.extended ? 9 : 4) + 1;
    const std::size_t digits = f.rtr ? 0 : 2u * f.dlc;
    if (out.size() != head + digits + (stamp ? 4 : 0) + 1) fuzz::fail("encoded frame of the wrong length: " + out);
    if (stamp) continue;
    const auto back = slcan::parse_line(std::string_view(out).substr(0, out.size() - 1));
    const auto* bc = std::get_if<slcan::Command>(&back);
    if (!bc || !(bc->frame == f)) fuzz::fail("encode/parse round trip changed the frame: " + out);
  }
  return 0;
}
