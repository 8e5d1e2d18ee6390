// Fuzz target: two RefGo connections (line assembler, session) on the interpreter of a real drive
// bundle (tests/support/device_fixture.hpp: dictionary, core, I/O functions, Store/Restore, the
// RefGo programs in the bundle's step) in drive time (refgo.md §1–§10). The drive is built fresh
// for every input, so that a crash reproduces from its input alone.
//
// Input: records [op][payload]; ops feed raw bytes to connection A or B, build a command line from
// the command table or an OR/OW of a real entry with fuzzed numbers, advance drive time by 1–256 ms,
// complete or fail pending state-file writes, or half-close A (then reconnect it).
// Drive time advances as under the server's manual clock (tests/fuzz/drive_time.hpp: quiet
// stretches skipped, needed steps in full; every other op touches the drive as a client's input
// wakes the clock). Budget per input (drive_time.hpp): 20 s of drive time, so that every timer the
// ops can set runs out, and 3 s of it in full steps — a Back & Forth with WT < 1000 ms (the short
// numbers the ops make) goes forth and back (refgo.md §7.7: ~1.1 s a way at RW100 WT999), a JP<t>
// timer stops the jog, a move settles. An idle drive passes it in a few full steps; an enabled one
// steps every ms (~2 µs a step under ASan: at most ~6 ms for an input).
// Oracles beyond "no crash, no sanitizer report": every reply has the layout of refgo.md §3
// ("<echo>\r\n[<answer>\r\n]>" or ">"), a connection's output only ever ends after a complete
// reply, every complete line gets exactly one reply once the writes are done (§2.5), and the
// dictionary is never corrupted.
#include <spdlog/spdlog.h>

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "protocols/line/line_assembler.hpp"
#include "protocols/refgo/codec.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "protocols/refgo/session.hpp"
#include "tests/fuzz/drive_bundle.hpp"
#include "tests/fuzz/drive_time.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using namespace mcemu;

constexpr std::array<const char*, 27> k_words = {"G",  "GW",  "SM", "CM", "PWC",  "PQ", "REF", "JP", "JN",
                                                 "RR", "OR",  "OW", "TP", "TPSR", "TS", "TI",  "SP", "AC",
                                                 "DE", "ACV", "PO", "WA", "SO",   "CO", "RW",  "WT", "XYZ"};

// The (index, sub) of every entry of the preset, for the OR/OW op: the same for every input.
std::vector<std::pair<std::uint16_t, std::uint8_t>> g_entries;

// One connection, with the reference framing that says how many replies it owes.
struct Connection {
  explicit Connection(refgo::Interpreter& in) : session(std::make_unique<refgo::Session>(in)) {}

  void feed(std::string_view bytes) {
    if (closed) return;
    lines += reference.feed(bytes).size();
    session->receive(bytes);
    collect();
  }
  void collect() {
    const std::string out = session->take_output();
    if (out.empty()) return;
    if (out.back() != '>') fuzz::fail("output ends inside a reply: " + out);
    parse_replies(out);
  }
  // refgo.md §3.1/§3.2: ">" alone, or an echo line, at most one answer line, then ">". Echoes and
  // answers never contain CR or LF (they are line ends in the request).
  void parse_replies(std::string_view out) {
    std::size_t i = 0;
    while (i < out.size()) {
      if (out[i] == '>') {
        ++replies;
        ++i;
        continue;
      }
      int lines_in_reply = 0;
      for (;;) {
        const auto crlf = out.find("\r\n", i);
        const auto bad = out.find_first_of("\r\n", i);
        if (crlf == std::string_view::npos || bad != crlf) fuzz::fail("reply line without CRLF: " + std::string(out));
        i = crlf + 2;
        if (++lines_in_reply > 2) fuzz::fail("reply with more than one answer line: " + std::string(out));
        if (i < out.size() && out[i] == '>') break;
        if (i >= out.size()) fuzz::fail("reply without prompt: " + std::string(out));
      }
      ++replies;
      ++i;
    }
  }

  std::unique_ptr<refgo::Session> session;
  line::LineAssembler reference{refgo::k_max_line, refgo::filter_byte};
  std::uint64_t lines = 0;
  std::uint64_t replies = 0;
  bool closed = false;
};

std::string number_text(fuzz::Records& r) {
  const auto v = static_cast<std::int32_t>(r.u16() | (static_cast<std::uint32_t>(r.u16()) << 16));
  switch (r.byte() % 4) {
    case 0: return std::to_string(v % 1000);
    case 1: return std::to_string(v);
    case 2: return std::to_string(static_cast<std::int64_t>(v) * 1000003);  // beyond 32 bits
    default: return {};
  }
}

std::string hex_of(unsigned v) {
  static constexpr char k_hex[] = "0123456789ABCDEF";
  std::string s;
  do {
    s.insert(s.begin(), k_hex[v % 16]);
    v /= 16;
  } while (v);
  return s;
}

mcemu::testing::DeviceOptions options() {
  mcemu::testing::DeviceOptions o;
  o.keep_events = false;
  return o;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  const mcemu::testing::DeviceFixture drive("MC349", options());
  drive.od().for_each([](const od::EntryInfo& e, const od::Value&) { g_entries.emplace_back(e.index, e.sub); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mcemu::testing::DeviceFixture drive("MC349", options());
  refgo::Interpreter& interpreter = drive.refgo();

  auto a = std::make_unique<Connection>(interpreter);
  Connection b(interpreter);
  std::vector<std::unique_ptr<Connection>> finished;  // half-closed, still owing replies
  fuzz::DriveTime drive_time(drive.device().steps());
  const auto collect_all = [&] {
    a->collect();
    b.collect();
    for (auto& c : finished) c->collect();
  };

  fuzz::Records r(data, size);
  while (!r.empty()) {
    const std::uint8_t op = r.byte();
    const unsigned op_kind = (op & 0x0F) % 9;  // 0x10 is a flag: the command goes to connection B
    switch (op_kind) {
      case 0: a->feed(r.bytes()); break;
      case 1: b.feed(r.bytes()); break;
      case 2: {  // a command of the table with a fuzzed argument and line end
        std::string line = k_words[r.byte() % k_words.size()];
        line += number_text(r);
        line += "\r\n\r"[r.byte() % 3];
        ((op & 0x10) ? static_cast<Connection&>(b) : *a).feed(line);
        break;
      }
      case 3: {  // OR / OW of a real entry
        const auto& [index, sub] = g_entries[r.u16() % g_entries.size()];
        const bool write = (r.byte() & 1) != 0;
        // appends, not operator+ chains: GCC 12 reports a false -Wrestrict for those
        std::string line = write ? "OW" : "OR";
        line.append(hex_of(index)).append(",").append(hex_of(sub));
        if (write) {
          line.append(",").append(number_text(r));
        } else if (r.byte() & 1) {
          line.append(",h");
        }
        line.push_back('\r');
        a->feed(line);
        break;
      }
      case 4: drive_time.advance(r.byte() + 1u); break;  // the programs too
      case 5: drive.storage().complete(true); break;
      case 6: drive.storage().complete(false); break;
      case 7: {  // FIN from A; the replies it owes still arrive, then a new connection takes its place
        a->session->peer_closed();
        a->closed = true;
        finished.push_back(std::move(a));
        a = std::make_unique<Connection>(interpreter);
        break;
      }
      default: interpreter.reset(); break;  // power-up state of the interpreter variables
    }
    if (op_kind != 4) drive_time.touch();  // the server's wake after a client's input
    collect_all();
  }

  while (drive.storage().pending() > 0) {
    drive.storage().complete(true);
    collect_all();
  }
  for (const Connection* c : {a.get(), &b}) {
    if (c->replies != c->lines) {
      fuzz::fail("connection answered " + std::to_string(c->replies) + " of " + std::to_string(c->lines) + " lines");
    }
  }
  for (const auto& c : finished) {
    if (c->replies != c->lines) fuzz::fail("half-closed connection lost replies");
    if (!c->session->finished()) fuzz::fail("half-closed connection never finished");
  }
  fuzz::check_dictionary(drive.od());
  return 0;
}
