// Fuzz target: what a WebSocket client sends and how its outbound queue behaves (web.md §10.2,
// §10.4) — the client-message parser applied to a subscription, and the per-client queue policy
// under any mix of status and other messages and sends. The frame layer is Beast's (web/net).
//
// Input: records [op][payload]; ops apply a client text (raw bytes or a subscribe/unsubscribe
// object built from the input) to one subscription, push a status or another message of a fuzzed
// size, or pop (send) messages.
// Oracles: a text that does not parse leaves the subscription unchanged; a parsed message applied
// twice gives the same subscription as applied once; the queued bytes of non-status messages never
// exceed the limit; a status popped is the newest one pushed (newest wins); the other messages
// come out in the order they were pushed; the byte count returns to 0 when the queue is empty.
#include <cstdint>
#include <memory>
#include <string>

#include "tests/fuzz/drive_bundle.hpp"
#include "web/api/ws_outbox.hpp"
#include "web/api/ws_protocol.hpp"

namespace {

using namespace mcemu;
using web::api::Subscription;
using web::api::WsOutbox;

constexpr const char* k_names[] = {"status", "scope", "trace", "udp", "STATUS", "", "refgo", "slcan", "http", "x"};

std::string built_message(fuzz::Records& r) {
  std::string s = "{";
  const unsigned fields = r.byte() % 4;
  for (unsigned f = 0; f < fields; ++f) {
    if (f) s += ',';
    static constexpr const char* k_keys[] = {"subscribe", "unsubscribe", "channels", "type"};
    s += '"';
    s += k_keys[r.byte() % 4];
    s += "\":";
    const unsigned kind = r.byte() % 4;
    if (kind == 0) {
      s += '"';
      s += k_names[r.byte() % std::size(k_names)];
      s += '"';
    } else if (kind == 1) {
      s += std::to_string(static_cast<int>(r.byte()) - 128);
    } else {
      s += '[';
      const unsigned n = r.byte() % 5;
      for (unsigned i = 0; i < n; ++i) {
        if (i) s += ',';
        s += '"';
        s += k_names[r.byte() % std::size(k_names)];
        s += '"';
      }
      s += ']';
    }
  }
  return s + "}";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Subscription sub;
  // Small enough that a few messages reach it, and no message costs kilobytes of memset under ASan.
  const std::size_t limit = 64 + 37 * 64;
  WsOutbox out(limit);
  std::uint64_t next_id = 0;
  std::uint64_t last_popped = 0;  // of the non-status messages
  std::uint64_t newest_status = 0;
  fuzz::Records r(data, size);
  while (!r.empty()) {
    const std::uint8_t op = r.byte();
    switch (op % 5) {
      case 0:
      case 1: {
        const std::string text = op % 5 == 0 ? std::string(r.bytes()) : built_message(r);
        const Subscription before = sub;
        const auto parsed = web::api::parse_client_message(text);
        const bool ok = web::api::apply_client_message(sub, text);
        if (ok != parsed.has_value()) fuzz::fail("apply and parse disagree on: " + text);
        if (!ok && !(sub == before)) fuzz::fail("a refused message changed the subscription: " + text);
        if (ok) {
          Subscription again = sub;
          web::api::apply(again, *parsed);
          if (!(again == sub)) fuzz::fail("applying twice differs from once: " + text);
        }
        break;
      }
      case 2: {  // a status snapshot: its text starts with its queue order
        newest_status = ++next_id;
        out.push_status(std::make_shared<const std::string>(std::to_string(newest_status) + ":status"));
        break;
      }
      case 3: {
        const std::size_t n = static_cast<std::size_t>(r.u16()) % (limit / 2);
        std::string m = std::to_string(++next_id) + ":";
        m.resize(std::max(m.size(), n), 'x');
        const std::size_t before = out.queued_bytes();
        const bool queued = out.push(std::make_shared<const std::string>(std::move(m)));
        if (!queued && out.queued_bytes() != before) fuzz::fail("a refused push changed the byte count");
        break;
      }
      default: {
        const unsigned n = r.byte() % 8 + 1;
        for (unsigned i = 0; i < n; ++i) {
          const auto m = out.pop();
          if (!m) break;
          const std::uint64_t id = std::stoull(m->substr(0, m->find(':')));
          if (m->ends_with(":status")) {
            if (id != newest_status) fuzz::fail("an older status was sent");
            continue;
          }
          if (id <= last_popped) fuzz::fail("messages out of order");
          last_popped = id;
        }
        break;
      }
    }
    if (out.queued_bytes() > out.limit()) fuzz::fail("queued bytes above the limit");
    if (out.empty() && out.queued_bytes() != 0) fuzz::fail("empty queue with bytes counted");
  }
  return 0;
}
