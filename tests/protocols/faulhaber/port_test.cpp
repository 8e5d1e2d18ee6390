// The port of faulhaber.md §2, §4–§6 with scripted owners: responses only to the requesting
// connection, asynchronous messages to all, the response before the notifications it caused, net
// mode, 0x2400.04 bits 16/17/23, node-id change, reset node, response delay in drive time, the
// output limit, pending writes, sessions that outlive the port, and the trace.
#include "protocols/faulhaber/port.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "protocols/faulhaber/describe.hpp"
#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

using namespace std::chrono_literals;
using test::bytes;
using test::request;
using test::wire;

std::string hex_of(const std::string& s) {
  return hex(std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
}
std::string frame_hex(const Frame& f) { return hex(encode(f)); }
// Hex strings joined as the output of one connection.
std::string join(std::initializer_list<std::string> parts) {
  std::string s;
  for (const auto& p : parts) {
    if (p.empty()) continue;
    if (!s.empty()) s += ' ';
    s += p;
  }
  return s;
}

// A stand-in for the drive core: a controlword write changes 6041h inside the write and records a
// StatuswordChanged event, which the owner hands to the port in after_request (as the server will).
struct Owner {
  explicit Owner(PortConfig config = {}) : od(test::make_dictionary()), port(*od, config, hooks()) {
    od->on_write(0x6040, 0, [this](od::WriteRequest& r) {
      if (refuse_controlword) return od::AbortCode::device_state;
      static const std::map<std::int64_t, std::int64_t> k_next = {
          {0x00, 0x0040}, {0x06, 0x0021}, {0x07, 0x0023}, {0x0F, 0x0027}, {0x1F, 0x0027}};
      const auto it = k_next.find(std::get<std::int64_t>(r.value));
      if (it != k_next.end() && it->second != od->number(0x6041, 0)) {
        test::set(*od, 0x6041, 0, it->second);
        events.push_back(static_cast<std::uint16_t>(it->second));
      }
      return od::AbortCode::none;
    });
  }

  Port::Hooks hooks() {
    Port::Hooks h;
    h.now = [this] { return now; };
    h.after_request = [this] {
      log.push_back("after_request");
      for (const auto sw : std::exchange(events, {})) port.notify_statusword(sw);
    };
    h.reset_node = [this] {
      log.push_back("reset_node");
      port.send_boot();  // the device reset itself is the owner's business
    };
    return h;
  }

  std::unique_ptr<od::ObjectDictionary> od;
  Port port;
  Millis now{0};
  bool refuse_controlword = false;
  std::vector<std::uint16_t> events;
  std::vector<std::string> log;
};

// One connection as the line adapter drives it: output collected after receive() and on wake-up.
struct Client {
  explicit Client(Port& port)
      : session(port.make_session([this](const TraceEvent& e) {
          trace.push_back({e.kind, std::string(e.hex), std::string(e.summary), e.command});
        })) {
    session->set_wake([this] {
      ++wakes;
      out += session->take_output();
    });
  }
  void send(std::string_view hex_text) { send_raw(wire(hex_text)); }
  void send_raw(const std::string& bytes_text) {
    session->receive(bytes_text);
    out += session->take_output();
  }
  std::string take() {
    out += session->take_output();
    return hex_of(std::exchange(out, {}));
  }
  std::vector<std::string> trace_lines() const {
    std::vector<std::string> v;
    for (const auto& e : trace) {
      static const char* k_kind[] = {"rx", "tx", "dropped", "ignored", "event"};
      v.push_back(std::string(k_kind[static_cast<int>(e.kind)]) + " " + e.summary);
    }
    return v;
  }

  struct Line {  // a TraceEvent's copy (its views die with the call)
    TraceEvent::Kind kind;
    std::string hex;
    std::string summary;
    std::uint8_t command;
  };
  std::vector<Line> trace;
  std::unique_ptr<line::StreamSession> session;
  std::string out;
  int wakes = 0;
};

struct Exchange {
  const char* name;
  std::function<void(Owner&)> setup;
  std::string input;      // host → drive bytes
  std::string requester;  // what the requesting connection receives
  std::string bystander;  // what another connection receives
};

const std::string k_sw_0021 = "53 06 01 05 21 00 23 45";
const std::string k_sw_0027 = "53 06 01 05 27 00 8F 45";
const std::string k_sw_0040 = "53 06 01 05 40 00 17 45";
const std::string k_write_6040 = "53 07 01 02 40 60 00 DB 45";
const std::string k_cw_ok = "53 05 01 04 00 55 45";
const std::string k_read_6041 = "53 07 01 01 41 60 00 73 45";

std::vector<Exchange> exchanges() {
  const auto set = [](std::uint16_t i, std::uint8_t s, std::int64_t v) {
    return [=](Owner& o) { test::set(*o.od, i, s, v); };
  };
  return {
      // the host → drive rows of §5 and their answers
      {"read 6041h = 0x0040", {}, k_read_6041, "53 09 01 01 41 60 00 40 00 C2 45", ""},
      {"read 6041h = 0x0427", set(0x6041, 0, 0x0427), k_read_6041, "53 09 01 01 41 60 00 27 04 F4 45", ""},
      {"write 6040h = 0x0006: response, then the notification",
       {},
       "53 09 01 02 40 60 00 06 00 2C 45",
       join({k_write_6040, k_sw_0021}),
       k_sw_0021},
      {"write 6040h = 0x000F from Ready to switch on", set(0x6041, 0, 0x0021), "53 09 01 02 40 60 00 0F 00 25 45",
       join({k_write_6040, k_sw_0027}), k_sw_0027},
      {"write 6060h = 3", {}, "53 08 01 02 60 60 00 03 A2 45", "53 07 01 02 60 60 00 FB 45", ""},
      {"write 60FFh = 100",
       {},
       "53 0B 01 02 FF 60 00 64 00 00 00 59 45",
       frame_hex(sdo_write_response(1, 0x60FF, 0)),
       ""},
      {"read 3005h.09 = -1", set(0x3005, 9, -1), "53 07 01 01 05 30 09 3B 45", "53 0B 01 01 05 30 09 FF FF FF FF 9D 45",
       ""},
      {"read 1234h.00", {}, "53 07 01 01 34 12 00 8B 45", "53 0B 01 03 34 12 00 00 00 02 06 2B 45", ""},
      {"write 6041h.00", {}, "53 09 01 02 41 60 00 00 00 2B 45", "53 0B 01 03 41 60 00 02 00 01 06 78 45", ""},
      {"reset node: the boot message to all",
       {},
       "53 04 01 00 50 45",
       "53 0B 01 00 4D 43 20 35 30 30 35 8E 45",
       "53 0B 01 00 4D 43 20 35 30 30 35 8E 45"},
      {"reset node with L = 6 (AN191)",
       {},
       request(0x00, "AA BB"),
       "53 0B 01 00 4D 43 20 35 30 30 35 8E 45",
       "53 0B 01 00 4D 43 20 35 30 30 35 8E 45"},
      {"controlword 0x0006", {}, "53 06 01 04 06 00 50 45", join({k_cw_ok, k_sw_0021}), k_sw_0021},
      {"controlword 0x000F", set(0x6041, 0, 0x0021), "53 06 01 04 0F 00 59 45", join({k_cw_ok, k_sw_0027}), k_sw_0027},
      {"write 2400h.04 = 0x00010000", {}, "53 0B 01 02 00 24 04 00 00 01 00 29 45", "53 07 01 02 00 24 04 8E 45", ""},
      {"abort request 1234h.00", {}, request(0x03, "34 12 00 00 00 00 08"), "53 07 01 03 34 12 00 DC 45", ""},
      // receiver rules through the port
      {"garbage before SOF", {}, "0D 0A 00 " + k_read_6041, "53 09 01 01 41 60 00 40 00 C2 45", ""},
      {"a stray S", {}, "53 00 " + k_read_6041, "53 09 01 01 41 60 00 40 00 C2 45", ""},
      {"wrong E", {}, "53 07 01 01 41 60 00 73 46 " + k_read_6041, "53 09 01 01 41 60 00 40 00 C2 45", ""},
      {"wrong CRC is dropped", {}, "53 07 01 01 41 60 00 00 45", "", ""},
      {"wrong CRC accepted with 0x2400.04 bit 23", set(0x2400, 4, 0x00830000), "53 07 01 01 41 60 00 00 45",
       "53 09 01 01 41 60 00 40 00 C2 45", ""},
      {"L < 4", {}, "53 03 01 00 50 45", "", ""},
      {"another node-id", {}, request(0x01, "41 60 00", 2), "", ""},
      {"two requests in one go",
       {},
       k_read_6041 + " " + request(0x01, "00 24 03"),
       join({"53 09 01 01 41 60 00 40 00 C2 45", frame_hex(Frame{1, 0x01, bytes("00 24 03 01")})}),
       ""},
      // the switches act on the very next frame, however the bytes are split
      {"bit 23 set, then a wrong CRC in the same chunk",
       {},
       request(0x02, "00 24 04 00 00 83 00") + " 53 07 01 01 41 60 00 00 45",
       join({frame_hex(sdo_write_response(1, 0x2400, 4)), "53 09 01 01 41 60 00 40 00 C2 45"}),
       ""},
      {"node-id 1 → 5: answered as 1, then only node 5 is answered",
       {},
       request(0x02, "00 24 03 05") + " " + k_read_6041 + " " + request(0x01, "41 60 00", 5),
       join({frame_hex(sdo_write_response(1, 0x2400, 3)), frame_hex(Frame{5, 0x01, bytes("41 60 00 40 00")})}),
       ""},
      // net mode: responses only
      {"net mode on: answered", {}, request(0x02, "00 24 05 01"), frame_hex(sdo_write_response(1, 0x2400, 5)), ""},
      {"net mode: no notification after a controlword", set(0x2400, 5, 1), "53 06 01 04 06 00 50 45", k_cw_ok, ""},
      {"net mode: no boot message after reset node", set(0x2400, 5, 1), "53 04 01 00 50 45", "", ""},
      {"net mode 2 is refused",
       {},
       request(0x02, "00 24 05 02"),
       frame_hex(sdo_error_response(1, 0x2400, 5, 0x06090030)),
       ""},
      // 0x2400.04 bits 16/17
      {"bit 17 off: no statusword notification", set(0x2400, 4, 0x00010000), "53 06 01 04 06 00 50 45", k_cw_ok, ""},
      {"bit 17 off: no boot message", set(0x2400, 4, 0x00010000), "53 04 01 00 50 45", "", ""},
      {"bit 16 off, bit 17 on: notification", set(0x2400, 4, 0x00020000), "53 06 01 04 06 00 50 45",
       join({k_cw_ok, k_sw_0021}), k_sw_0021},
      {"a 1-byte write of 0x2400.04",
       {},
       request(0x02, "00 24 04 00"),
       frame_hex(sdo_error_response(1, 0x2400, 4, 0x06070013)),
       ""},
      {"controlword refused: error byte 1, no notification", [](Owner& o) { o.refuse_controlword = true; },
       "53 06 01 04 06 00 50 45", frame_hex(controlword_response(1, 1)), ""},
  };
}

// Runs an exchange with the input cut at the given offsets (every chunk at a later drive time, 1 ms
// apart: well inside the inter-byte timeout).
std::pair<std::string, std::string> run(const Exchange& x, const std::vector<std::size_t>& cuts) {
  Owner o;
  if (x.setup) x.setup(o);
  Client a(o.port);
  Client b(o.port);
  const std::string in = wire(x.input);
  std::size_t from = 0;
  for (const std::size_t cut : cuts) {
    a.send_raw(in.substr(from, cut - from));
    o.now += 1ms;
    from = cut;
  }
  a.send_raw(in.substr(from));
  return {a.take(), b.take()};
}

TEST(Port, ExchangesWholeAndSplitAtEveryOffset) {
  for (const auto& x : exchanges()) {
    const auto whole = run(x, {});
    EXPECT_EQ(whole.first, x.requester) << x.name;
    EXPECT_EQ(whole.second, x.bystander) << x.name;
    const std::size_t n = wire(x.input).size();
    for (std::size_t cut = 0; cut <= n; ++cut) {
      EXPECT_EQ(run(x, {cut}), whole) << x.name << ", cut at " << cut;
    }
    std::vector<std::size_t> every;
    for (std::size_t i = 1; i < n; ++i) every.push_back(i);
    EXPECT_EQ(run(x, every), whole) << x.name << ", byte by byte";
  }
}

TEST(Port, AsynchronousRowsGoToEveryConnection) {
  Owner o;
  Client a(o.port);
  Client b(o.port);
  o.port.notify_statusword(0x0040);
  o.port.notify_statusword(0x0021);
  o.port.notify_statusword(0x0027);
  o.port.notify_statusword(0x0427);
  o.port.notify_emcy(0x3210, 0x05, 0x0004);
  o.port.notify_emcy(0x0000, 0x00, 0x0000);
  o.port.notify_emcy(0x8611, 0x21, 0x0002);
  o.port.send_boot();
  (void)o.od->write(0x1008, 0, od::Value{std::string("MCS 3242 BX4 ET")}, od::Origin::internal);
  o.port.send_boot();
  const std::string want =
      join({"53 06 01 05 40 00 17 45", "53 06 01 05 21 00 23 45", "53 06 01 05 27 00 8F 45", "53 06 01 05 27 04 21 45",
            "53 0C 01 07 10 32 05 04 00 00 00 00 83 45", "53 0C 01 07 00 00 00 00 00 00 00 00 A0 45",
            "53 0C 01 07 11 86 21 02 00 00 00 00 14 45", "53 0B 01 00 4D 43 20 35 30 30 35 8E 45",
            "53 13 01 00 4D 43 53 20 33 32 34 32 20 42 58 34 20 45 54 A8 45"});
  EXPECT_EQ(a.take(), want);
  EXPECT_EQ(b.take(), want);
  EXPECT_EQ(a.wakes, 9) << "output outside a receive() call wakes the adapter";
}

TEST(Port, NothingIsSentOnConnect) {
  Owner o;
  Client a(o.port);
  EXPECT_EQ(a.take(), "");
  o.port.send_boot();
  Client b(o.port);
  EXPECT_EQ(b.take(), "") << "a newly connected client does not get the boot message (§6)";
  o.port.notify_statusword(0x0040);
  EXPECT_EQ(b.take(), "53 06 01 05 40 00 17 45");
  EXPECT_EQ(o.port.session_count(), 2u);
}

TEST(Port, SwitchesOfAsynchronousMessages) {
  struct Case {
    std::int64_t settings;
    std::int64_t net_mode;
    bool emcy;
    bool async;
  };
  const Case cases[] = {{0x00030000, 0, true, true},   {0x00010000, 0, true, false},  {0x00020000, 0, false, true},
                        {0x00000000, 0, false, false}, {0x00030000, 1, false, false}, {0x00830000, 0, true, true}};
  for (const auto& c : cases) {
    Owner o;
    test::set(*o.od, 0x2400, 4, c.settings);
    test::set(*o.od, 0x2400, 5, c.net_mode);
    Client a(o.port);
    o.port.notify_emcy(0x3210, 0x05, 0x0004);
    EXPECT_EQ(a.take(), c.emcy ? "53 0C 01 07 10 32 05 04 00 00 00 00 83 45" : "") << c.settings;
    o.port.notify_statusword(0x0040);
    EXPECT_EQ(a.take(), c.async ? "53 06 01 05 40 00 17 45" : "") << c.settings;
    o.port.send_boot();
    EXPECT_EQ(a.take(), c.async ? "53 0B 01 00 4D 43 20 35 30 30 35 8E 45" : "") << c.settings;
    EXPECT_EQ(o.port.emcy_enabled(), c.emcy);
    EXPECT_EQ(o.port.async_enabled(), c.async);
    EXPECT_EQ(o.port.net_mode(), c.net_mode == 1);
  }
}

TEST(Port, ResetNodeCallsTheOwnerThenAfterRequest) {
  for (const std::string& req : {std::string("53 04 01 00 50 45"), request(0x00, "12 34")}) {
    Owner o;
    Client a(o.port);
    a.send(req);
    EXPECT_EQ(o.log, (std::vector<std::string>{"reset_node", "after_request"})) << req;
    EXPECT_EQ(a.take(), "53 0B 01 00 4D 43 20 35 30 30 35 8E 45") << "no direct response, then the boot message";
  }
}

TEST(Port, AfterRequestRunsOncePerHandledRequestOnly) {
  Owner o;
  Client a(o.port);
  a.send(k_read_6041 + " " + request(0x06, "") + " " + request(0x01, "41 60 00", 3) + " 53 07 01 01 41 60 00 00 45");
  EXPECT_EQ(o.log, (std::vector<std::string>{"after_request", "after_request"}))
      << "two requests for this node; another node's frame and a bad CRC are not requests";
}

TEST(Port, NodeIdChangeAppliesToAsynchronousMessages) {
  Owner o;
  Client a(o.port);
  a.send(request(0x02, "00 24 03 05"));
  EXPECT_EQ(a.take(), frame_hex(sdo_write_response(1, 0x2400, 3)));
  EXPECT_EQ(o.port.node_id(), 5);
  o.port.notify_statusword(0x0040);
  EXPECT_EQ(a.take(), frame_hex(statusword_notification(5, 0x0040)));
  a.send(k_read_6041);
  EXPECT_EQ(a.take(), "");
  EXPECT_EQ(a.trace_lines().back(), "ignored for node 1, this drive is node 5");
}

TEST(Port, ResponseDelayInDriveTime) {
  PortConfig cfg;
  cfg.response_delay = 5ms;
  Owner o(cfg);
  Client a(o.port);
  Client b(o.port);
  o.now = 100ms;
  a.send("53 06 01 04 06 00 50 45");  // answer held back; its notification waits behind it on A only
  EXPECT_EQ(a.take(), "");
  EXPECT_EQ(b.take(), k_sw_0021);
  EXPECT_EQ(o.port.next_deadline(), std::optional<Millis>(105ms));
  o.now = 102ms;
  a.send(k_read_6041);  // a second request: its answer after the first, 5 ms after it arrived
  o.port.step(104ms);
  EXPECT_EQ(a.take(), "");
  o.port.step(105ms);
  EXPECT_EQ(a.take(), join({k_cw_ok, k_sw_0021}));
  EXPECT_EQ(o.port.next_deadline(), std::optional<Millis>(107ms));
  o.port.step(110ms);
  EXPECT_EQ(a.take(), frame_hex(Frame{1, command::sdo_read, bytes("41 60 00 21 00")}));
  EXPECT_EQ(o.port.next_deadline(), std::nullopt);
  EXPECT_GE(a.wakes, 2);
}

TEST(Port, PendingWriteHoldsLaterOutputInOrder) {
  Owner o;
  od::Done held;
  o.od->on_write(0x1010, 1, [&held](od::WriteRequest& r) {
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  Client a(o.port);
  a.send(request(0x02, "10 10 01 73 61 76 65") + " " + k_read_6041);
  o.port.notify_statusword(0x0040);
  EXPECT_EQ(a.take(), "");
  EXPECT_FALSE(a.session->finished());
  EXPECT_EQ(o.port.next_deadline(), std::nullopt);
  held(od::AbortCode::none);
  EXPECT_EQ(a.take(), join({frame_hex(sdo_write_response(1, 0x1010, 1)), "53 09 01 01 41 60 00 40 00 C2 45",
                            "53 06 01 05 40 00 17 45"}));
}

TEST(Port, PendingWriteCompletedInsideTheWrite) {
  Owner o;
  o.od->on_write(0x1010, 1, [](od::WriteRequest& r) {
    (*r.done)(od::AbortCode::cannot_store);
    return od::AbortCode::pending;
  });
  Client a(o.port);
  a.send(request(0x02, "10 10 01 73 61 76 65") + " " + k_read_6041);
  EXPECT_EQ(a.take(),
            join({frame_hex(sdo_error_response(1, 0x1010, 1, 0x08000020)), "53 09 01 01 41 60 00 40 00 C2 45"}));
}

TEST(Port, PendingWriteOfAClosedConnectionGoesNowhere) {
  Owner o;
  od::Done held;
  o.od->on_write(0x1010, 1, [&held](od::WriteRequest& r) {
    held = std::move(*r.done);
    return od::AbortCode::pending;
  });
  {
    Client a(o.port);
    a.send(request(0x02, "10 10 01 73 61 76 65"));
  }
  Client b(o.port);
  held(od::AbortCode::none);
  EXPECT_EQ(b.take(), "");
  EXPECT_EQ(o.port.session_count(), 1u);
}

TEST(Port, OutputLimitStopsTheSession) {
  PortConfig cfg;
  cfg.queue_limit_bytes = 1024;
  Owner o(cfg);
  auto session = o.port.make_session();
  std::string many;
  for (int i = 0; i < 100; ++i) many += wire(k_read_6041);  // 100 answers of 11 bytes > 1024
  session->receive(many);
  EXPECT_TRUE(session->finished());
  const std::string out = session->take_output();
  EXPECT_GT(out.size(), 1024u) << "everything goes to the adapter at once, whose limit closes the connection";
  session->receive(many);
  o.port.notify_statusword(0x0040);
  EXPECT_EQ(session->take_output(), "") << "a stopped session is silent";
}

TEST(Port, OutputLimitCountsHeldBackOutput) {
  PortConfig cfg;
  cfg.queue_limit_bytes = 1024;
  cfg.response_delay = 5ms;
  Owner o(cfg);
  Client a(o.port);
  for (int i = 0; i < 93; ++i) a.send(k_read_6041);  // 93 × 11 = 1023 bytes held
  EXPECT_FALSE(a.session->finished());
  EXPECT_EQ(a.take(), "");
  a.send(k_read_6041);
  EXPECT_TRUE(a.session->finished());
  EXPECT_EQ(a.take().size(), 94u * 11u * 3u - 1u);
  EXPECT_EQ(a.trace_lines().back(), "event closing: output queue above 1024 bytes");
}

TEST(Port, SessionOutlivesThePort) {
  auto o = std::make_unique<Owner>();
  Client a(o->port);
  a.send(k_read_6041);
  EXPECT_EQ(a.take(), "53 09 01 01 41 60 00 40 00 C2 45");
  o.reset();
  a.send(k_read_6041);
  EXPECT_EQ(a.take(), "");
  EXPECT_TRUE(a.session->finished());
  a.session->peer_closed();
  a.session->closing("queue overflow");
}

TEST(Port, PeerClosed) {
  Owner o;
  Client a(o.port);
  const std::string req = wire(k_read_6041);
  a.send_raw(req.substr(0, 4));
  a.session->peer_closed();
  EXPECT_TRUE(a.session->finished());
  a.send_raw(req.substr(4));
  o.port.notify_statusword(0x0040);
  EXPECT_EQ(a.take(), "") << "the partial frame is gone; no notifications after FIN";
}

TEST(Port, AWakeUpThatDestroysAnotherSessionIsSafe) {
  Owner o;
  Client a(o.port);
  auto b = std::make_unique<Client>(o.port);
  a.session->set_wake([&] { b.reset(); });  // the adapter closing B (woken after A) while A is woken
  o.port.notify_statusword(0x0040);
  o.port.notify_statusword(0x0021);
  EXPECT_EQ(o.port.session_count(), 1u);
}

TEST(Port, Trace) {
  Owner o;
  Client a(o.port);
  a.send("00 " + request(0x02, "40 60 00 0F 00") + " 53 07 01 01 41 60 00 00 45 " + request(0x01, "41 60 00", 2));
  o.port.send_boot();
  o.port.notify_emcy(0x3210, 0x05, 0x0004);
  a.send(request(0x01, "34 12 00"));
  a.session->closing("idle timeout");
  EXPECT_EQ(a.trace_lines(), (std::vector<std::string>{
                                 "dropped garbage before SOF",
                                 "rx SDO write 6040.00 = 0x000F",
                                 "tx SDO write 6040.00 ok",
                                 "tx statusword 0x0027",
                                 "dropped bad CRC",
                                 "rx SDO read 6041.00",
                                 "ignored for node 2, this drive is node 1",
                                 "tx boot \"MC 5005\"",
                                 "tx EMCY 3210h reg 05 word 0004",
                                 "rx SDO read 1234.00",
                                 "tx error 1234.00 0x06020000",
                                 "event closing: idle timeout",
                             }));
  EXPECT_EQ(a.trace[1].hex, "53 09 01 02 40 60 00 0F 00 25 45");
  EXPECT_EQ(a.trace[2].hex, "53 07 01 02 40 60 00 DB 45");
  EXPECT_EQ(a.trace[4].hex, "53 07 01 01 41 60 00 00 45");
  EXPECT_EQ(a.trace[0].hex, "00");
  // the command byte of each frame (the master lint tells responses from notifications by it)
  std::vector<int> commands;
  for (const auto& l : a.trace) commands.push_back(l.command);
  EXPECT_EQ(commands, (std::vector<int>{0, 0x02, 0x02, 0x05, 0, 0x01, 0, 0x00, 0x07, 0x01, 0x03, 0}));
}

TEST(Port, TraceOfARefusedControlwordNamesTheCode) {
  Owner o;
  o.refuse_controlword = true;
  Client a(o.port);
  a.send("53 06 01 04 06 00 50 45");
  EXPECT_EQ(a.trace_lines().back(), "tx controlword refused (error 1) 0x08000022");
}

TEST(Port, WithoutANowHookTimeIsTheLastStep) {
  auto od = test::make_dictionary();
  PortConfig cfg;
  cfg.response_delay = 2ms;
  Port port(*od, cfg);
  auto s = port.make_session();
  port.step(10ms);
  s->receive(wire(k_read_6041));
  EXPECT_EQ(port.next_deadline(), std::optional<Millis>(12ms));
  port.step(12ms);
  EXPECT_EQ(hex_of(s->take_output()), "53 09 01 01 41 60 00 40 00 C2 45");
}

TEST(Port, DefaultsWithoutThe2400Entries) {
  od::ObjectDictionary od(std::vector<od::EntryInfo>{test::entry(0x6041, 0, od::DataType::unsigned16, od::Access::ro)});
  Port port(od, {});
  EXPECT_EQ(port.node_id(), 1);
  EXPECT_TRUE(port.crc_check());
  EXPECT_TRUE(port.async_enabled());
  EXPECT_TRUE(port.emcy_enabled());
  EXPECT_FALSE(port.net_mode());
  auto s = port.make_session();
  port.send_boot();  // no 1008h: an empty name
  EXPECT_EQ(hex_of(s->take_output()), frame_hex(boot_message(1, "")));
}

// The trace channel's line of each kind of event (server/drive_listeners.cpp records it), built in
// the caller's buffer: once it has grown, a stream of frames reuses it.
TEST(TraceLine, EveryKindAndTheBufferIsReused) {
  using K = TraceEvent::Kind;
  const struct {
    TraceEvent e;
    const char* want;
  } rows[] = {
      {{K::rx, "53 07 01 01 41 60 00 73 45", "SDO read 6041.00"}, "53 07 01 01 41 60 00 73 45 | SDO read 6041.00"},
      {{K::tx, "53 05 01 04 00 55 45", "controlword ok"}, "53 05 01 04 00 55 45 | controlword ok"},
      {{K::dropped, "53 03", "length 3 < 4"}, "dropped 53 03 | length 3 < 4"},
      {{K::ignored, "", "node 2, not 1"}, "ignored node 2, not 1"},
      {{K::event, "", "closing: queue overflow"}, "closing: queue overflow"},
      {{K::rx, "53 04 01 00 50 45", ""}, "53 04 01 00 50 45"},
  };
  std::string out = "left over from before";
  for (const auto& r : rows) {
    trace_line(r.e, out);
    EXPECT_EQ(out, r.want);
  }
  out.reserve(256);
  const char* buffer = out.data();
  const auto capacity = out.capacity();
  for (const auto& r : rows) trace_line(r.e, out);
  EXPECT_EQ(out.data(), buffer) << "the buffer is reused, not replaced";
  EXPECT_EQ(out.capacity(), capacity);
}

}  // namespace
}  // namespace mcemu::faulhaber
