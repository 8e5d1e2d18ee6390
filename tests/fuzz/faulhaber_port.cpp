// Fuzz target: the FAULHABER port (faulhaber.md §4–§6) — two connections, the receiver, the command
// table and the asynchronous messages — on a small dictionary with a stand-in for the drive core
// (a controlword write changes 6041h and raises a statusword event, handed to the port after each
// request) and a Store entry (1010h.01) whose writes complete when the input says so.
//
// Input: one flag byte (response delay, output limit), then records [op][payload]. Besides raw
// bytes, ops build well-formed requests (any command code, this or another node-id, the index/sub
// of a real entry, 0 … 5 value bytes) fed in two pieces, notifications, boot, drive time, Store
// completions, 0x2400 settings written by the owner, reconnects and FINs.
// Oracles beyond "no crash, no sanitizer report": every connection's output is a sequence of whole
// frames with correct CRCs and drive-side command codes; with asynchronous messages off nothing is
// sent on a notify call; once every Store has completed and time has run past every delay, each
// connection got exactly one response per request for this drive (reset node excepted); the
// dictionary is never corrupted.
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "protocols/faulhaber/crc.hpp"
#include "protocols/faulhaber/port.hpp"

namespace {

using namespace mcemu;
using namespace mcemu::faulhaber;
using namespace std::chrono_literals;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

class Records {
 public:
  Records(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  bool empty() const { return p_ >= end_; }
  std::uint8_t byte() { return p_ < end_ ? *p_++ : 0; }
  std::uint16_t u16() {
    const std::uint16_t lo = byte();
    return static_cast<std::uint16_t>(lo | (byte() << 8));
  }
  std::string bytes() {
    const std::size_t n = std::min<std::size_t>(byte(), static_cast<std::size_t>(end_ - p_));
    std::string s(reinterpret_cast<const char*>(p_), n);
    p_ += n;
    return s;
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

od::EntryInfo entry(std::uint16_t index, std::uint8_t sub, od::DataType type, od::Access access,
                    od::Value factory = std::int64_t{0}) {
  od::EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.type = type;
  e.access = access;
  e.factory = std::move(factory);
  e.name = "fuzz";
  return e;
}

std::vector<od::EntryInfo> entries() {
  using od::Access;
  using od::DataType;
  std::vector<od::EntryInfo> v = {
      entry(0x1001, 0, DataType::unsigned8, Access::ro),
      entry(0x1008, 0, DataType::visible_string, Access::const_, std::string("MC 5005")),
      entry(0x1010, 1, DataType::unsigned32, Access::rw),
      entry(0x2400, 3, DataType::unsigned8, Access::rw, std::int64_t{1}),
      entry(0x2400, 4, DataType::unsigned32, Access::rw, std::int64_t{0x00030000}),
      entry(0x2400, 5, DataType::unsigned8, Access::rw),
      entry(0x3005, 0, DataType::unsigned8, Access::ro, std::int64_t{26}),
      entry(0x6040, 0, DataType::unsigned16, Access::rw),
      entry(0x6041, 0, DataType::unsigned16, Access::ro, std::int64_t{0x0040}),
      entry(0x6060, 0, DataType::integer8, Access::rw),
      entry(0x60FF, 0, DataType::integer32, Access::rw),
  };
  v[3].limits = od::Range{1, 255};
  v[5].validator = [](const od::ObjectDictionary&, std::optional<std::int64_t>, std::int64_t next) {
    return next > 1 ? od::AbortCode::invalid_value : od::AbortCode::none;
  };
  for (std::uint8_t s = 1; s <= 0x1A; ++s) v.push_back(entry(0x3005, s, DataType::integer32, Access::rw));
  return v;
}

struct Client {
  explicit Client(Port& port) {
    session = port.make_session([this](const TraceEvent& e) { on_trace(e); });
    session->set_wake([this] { collect(); });
  }
  void on_trace(const TraceEvent& e) {
    if (e.kind == TraceEvent::Kind::rx) {
      last_counted = e.summary.rfind("reset node", 0) != 0;
      if (last_counted) ++requests;
    } else if (e.kind == TraceEvent::Kind::ignored) {
      if (last_counted) --requests;
    } else if (e.kind == TraceEvent::Kind::event && e.summary.rfind("closing: output queue", 0) == 0) {
      overflowed = true;
    }
  }
  // Takes the session's output and checks it frame by frame: the port writes whole frames only.
  void collect() {
    const std::string out = session->take_output();
    std::size_t i = 0;
    while (i < out.size()) {
      const auto* b = reinterpret_cast<const std::uint8_t*>(out.data()) + i;
      const std::size_t left = out.size() - i;
      if (left < 6 || b[0] != k_sof || b[1] < 4 || left < b[1] + 2u || b[b[1] + 1] != k_eof) {
        fail("output is not a sequence of whole frames");
      }
      const std::span<const std::uint8_t> f(b, b[1] + 2u);
      if (crc8(f.subspan(1, b[1] - 1)) != b[b[1]]) fail("the drive sent a wrong CRC");
      switch (b[3]) {
        case command::sdo_read:
        case command::sdo_write:
        case command::sdo_error:
        case command::controlword: ++responses; break;
        case command::boot:
        case command::statusword:
        case command::emcy: ++notifications; break;
        default: fail("the drive sent command code " + std::to_string(b[3]));
      }
      i += f.size();
    }
    received += out.size();
  }

  std::unique_ptr<line::StreamSession> session;
  std::uint64_t requests = 0;
  std::uint64_t responses = 0;
  std::uint64_t notifications = 0;
  std::uint64_t received = 0;
  bool last_counted = false;
  bool overflowed = false;
  bool fin = false;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto k_entries = entries();
  od::ObjectDictionary od(k_entries);
  Records r(data, size);
  const std::uint8_t flags = r.byte();
  PortConfig config;
  static constexpr Millis k_delays[] = {0ms, 1ms, 5ms, 20ms};
  config.response_delay = k_delays[flags & 3];
  config.queue_limit_bytes = (flags & 4) ? 1024 : 64 * 1024;

  Millis now{0};
  std::vector<std::uint16_t> events;
  std::deque<od::Done> stores;
  std::unique_ptr<Port> port_holder;
  Port::Hooks hooks;
  hooks.now = [&now] { return now; };
  hooks.after_request = [&] {
    for (const auto sw : std::exchange(events, {})) port_holder->notify_statusword(sw);
  };
  hooks.reset_node = [&] { port_holder->send_boot(); };
  port_holder = std::make_unique<Port>(od, config, hooks);
  Port& port = *port_holder;

  od.on_write(0x6040, 0, [&](od::WriteRequest& w) {
    const auto cw = std::get<std::int64_t>(w.value);
    if (cw == 0xDEAD) return od::AbortCode::device_state;  // a refusing core
    const std::int64_t sw = (cw & 0x0F) == 0x0F ? 0x0027 : (cw & 0x06) == 0x06 ? 0x0021 : 0x0040;
    if (sw != od.number(0x6041, 0)) {
      (void)od.write(0x6041, 0, od::Value{sw}, od::Origin::internal);
      events.push_back(static_cast<std::uint16_t>(sw));
    }
    return od::AbortCode::none;
  });
  od.on_write(0x1010, 1, [&](od::WriteRequest& w) {
    stores.push_back(std::move(*w.done));
    return od::AbortCode::pending;
  });

  std::vector<std::pair<std::uint16_t, std::uint8_t>> addresses;
  od.for_each([&](const od::EntryInfo& e, const od::Value&) { addresses.emplace_back(e.index, e.sub); });
  addresses.emplace_back(0x1234, 0);  // missing

  std::unique_ptr<Client> clients[2] = {std::make_unique<Client>(port), std::make_unique<Client>(port)};
  const auto sent_total = [&] { return clients[0]->received + clients[1]->received; };
  const auto collect = [&] {
    for (auto& c : clients) c->collect();
  };

  while (!r.empty()) {
    const std::uint8_t op = r.byte();
    Client& c = *clients[(op >> 7) & 1];
    switch ((op & 0x7F) % 10) {
      case 0: c.session->receive(r.bytes()); break;
      case 1: {  // a well-formed request, fed in two pieces
        Frame f;
        f.command = static_cast<std::uint8_t>(r.byte() % 16);
        const std::uint8_t node_pick = r.byte();
        f.node = (node_pick & 0x80) ? node_pick : port.node_id();
        const auto& [index, sub] = addresses[r.u16() % addresses.size()];
        const std::uint8_t shape = r.byte();
        if (shape & 0x80) {
          f.data = {static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8), sub};
          if (f.command == command::controlword) f.data.clear();
        }
        for (unsigned k = 0; k < shape % 6u; ++k) f.data.push_back(r.byte());
        const auto wire = encode(f);
        const std::size_t cut = r.byte() % (wire.size() + 1);
        const std::string text(wire.begin(), wire.end());
        c.session->receive(std::string_view(text).substr(0, cut));
        c.session->receive(std::string_view(text).substr(cut));
        break;
      }
      case 2:
      case 3:
      case 4: {
        collect();
        const bool async = port.async_enabled();
        const bool emcy = port.emcy_enabled();
        const std::uint64_t before = sent_total();
        const std::uint8_t kind = (op & 0x7F) % 10;
        if (kind == 2) port.notify_statusword(r.u16());
        if (kind == 3) port.notify_emcy(r.u16(), r.byte(), r.u16());
        if (kind == 4) port.send_boot();
        collect();
        const bool enabled = kind == 3 ? emcy : async;
        if (!enabled && sent_total() != before) fail("an asynchronous message while switched off");
        break;
      }
      case 5:
        now += Millis(r.byte());
        port.step(now);
        break;
      case 6: {  // the oldest Store completes, durably or not
        const bool ok = (r.byte() & 1) != 0;
        if (!stores.empty()) {
          auto done = std::move(stores.front());
          stores.pop_front();
          if (done) done(ok ? od::AbortCode::none : od::AbortCode::cannot_store);
        }
        break;
      }
      case 7: clients[(op >> 7) & 1] = std::make_unique<Client>(port); break;
      case 8:
        c.session->peer_closed();
        c.fin = true;
        break;
      default: {  // the owner (web, script) changes a communication setting
        static constexpr std::uint8_t k_subs[] = {3, 4, 5};
        const std::uint8_t sub = k_subs[r.byte() % 3];
        (void)od.write(0x2400, sub, od::Value{static_cast<std::int64_t>(r.u16()) << (sub == 4 ? 8 : 0)},
                       od::Origin::web);
        break;
      }
    }
    collect();
    if (port.session_count() != 2) fail("session count");
  }

  while (!stores.empty()) {
    auto done = std::move(stores.front());
    stores.pop_front();
    if (done) done(od::AbortCode::none);
  }
  now += 1000ms;
  port.step(now);
  collect();
  if (port.next_deadline()) fail("output still held back after every delay");
  for (const auto& c : clients) {
    if (c->overflowed) continue;
    if (c->responses != c->requests) {
      fail("connection got " + std::to_string(c->responses) + " responses to " + std::to_string(c->requests) +
           " requests");
    }
  }
  od.for_each([](const od::EntryInfo& info, const od::Value& v) {
    if (!od::convert_for_write(info, v)) fail("entry " + std::to_string(info.index) + " holds a bad value");
  });
  return 0;
}
