// Fuzz target: two SLCAN connections (line assembler, codec, session) on the one virtual CAN bus of
// a real drive bundle (tests/support/device_fixture.hpp; device().canopen(), device/canopen_bus.cpp)
// with the CANopen node of node-id 50 and the drive — dictionary, core, I/O functions,
// Store/Restore, NMT reset wiring — in drive time (slcan-canopen.md §3–§10). The drive is built
// fresh for every input, so that a crash reproduces from its input alone.
//
// Input: two bytes of session settings, then records [op][payload]. Besides raw bytes, ops build well-formed frames so
// that the fuzzer reaches deep SDO states: any SDO command specifier with the index/sub of a real entry; complete
// expedited, segmented and block (CRC) transfers that the next ops can interrupt; NMT, SYNC, RPDO
// and guarding frames; advancing drive time by 1–256 ms or by 0–5100 ms; state-file writes
// completing or failing.
// Drive time advances as under the server's manual clock (tests/fuzz/drive_time.hpp: quiet
// stretches skipped, needed steps in full; every other op touches the drive as a client's input
// wakes the clock). Budget per input (drive_time.hpp): 20 s of drive time, 3 s of it in full steps:
// SDO server timeouts (1 s), heartbeats and guarding, boot-up delays still happen, also while a
// drive enabled over SDO needs every step; an idle drive passes it in a few full steps.
// Oracles beyond "no crash, no sanitizer report": every complete line gets exactly one reply in
// order (§3.2 rule 5); every line mcemu sends is a reply of §3.4 or a frame line that parses back
// (§3.6: upper-case hex, digits = 2·DLC, CR only); the dictionary is never corrupted.
#include <spdlog/spdlog.h>

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "protocols/canopen/crc16.hpp"
#include "protocols/line/line_assembler.hpp"
#include "protocols/slcan/codec.hpp"
#include "protocols/slcan/session.hpp"
#include "tests/fuzz/drive_bundle.hpp"
#include "tests/fuzz/drive_time.hpp"
#include "tests/support/device_fixture.hpp"

namespace {

using namespace mcemu;
using namespace std::chrono_literals;

constexpr std::uint16_t k_sdo_rx = 0x600 + 50;

// One SLCAN connection: a session the bus made (it leaves the bus when destroyed).
struct Client {
  explicit Client(device::CanopenBus& bus) : session(bus.make_session()) {}

  void feed(std::string_view bytes) {
    if (closed) return;
    lines += reference.feed(bytes).size();
    session->receive(bytes);
  }
  // Splits the output into units (BEL, or text up to CR) and checks each.
  void collect() {
    const std::string out = session->take_output();
    std::size_t i = 0;
    while (i < out.size()) {
      if (out[i] == '\a') {
        ++replies;
        ++i;
        continue;
      }
      const auto cr = out.find('\r', i);
      if (cr == std::string::npos) fuzz::fail("output line without CR: " + out);
      const std::string_view unit(out.data() + i, cr - i);
      i = cr + 1;
      if (unit.find_first_of("\n\a") != std::string_view::npos) fuzz::fail("LF or BEL inside a line: " + out);
      if (!unit.empty() && unit[0] == 't') {
        check_frame_line(unit);
      } else {
        ++replies;
      }
    }
  }
  static void check_frame_line(std::string_view unit) {
    // a frame line the node sent: parses back to an 11-bit data frame (a Z1 timestamp adds 4 digits)
    auto r = slcan::parse_line(unit);
    if (!std::holds_alternative<slcan::Command>(r) && unit.size() >= 4) {
      r = slcan::parse_line(unit.substr(0, unit.size() - 4));
    }
    const auto* c = std::get_if<slcan::Command>(&r);
    if (!c || c->kind != slcan::CommandKind::frame || c->frame.extended || c->frame.rtr) {
      fuzz::fail("node sent a malformed frame line: " + std::string(unit));
    }
    if (unit.find_first_of("abcdef") != std::string_view::npos) fuzz::fail("lower-case hex: " + std::string(unit));
  }

  std::unique_ptr<line::StreamSession> session;
  line::LineAssembler reference{slcan::Session::k_max_line, line::keep_all};
  std::uint64_t lines = 0;
  std::uint64_t replies = 0;
  bool closed = false;
};

std::string sdo_line(const std::array<std::uint8_t, 8>& d, std::uint16_t id = k_sdo_rx, std::uint8_t dlc = 8) {
  can::Frame f;
  f.id = id;
  f.dlc = dlc;
  f.data = d;
  return slcan::encode_frame(f);
}

// The (index, sub) of every entry of the preset, for the SDO ops: the same for every input.
std::vector<std::pair<std::uint16_t, std::uint8_t>> g_entries;

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
  fuzz::Records r(data, size);
  // the session settings of the "slcan" config section, as --config gives them
  static constexpr std::array<const char*, 3> k_acks = {"z", "cr", "none"};
  const std::uint8_t ack = r.byte() % 3;
  const int digits = (r.byte() & 1) ? 8 : 4;
  mcemu::testing::DeviceOptions settings = options();
  settings.config = {{"slcan", {{"frame_ack", k_acks[ack]}, {"serial_digits", digits}}}};
  mcemu::testing::DeviceFixture drive("MC349", std::move(settings));
  device::CanopenBus& bus = *drive.device().canopen();

  Client a(bus);
  Client b(bus);
  drive.device().power_up_network();                   // boot-up, as at the start of mcemu
  fuzz::DriveTime drive_time(drive.device().steps());  // the bus too
  // what the node has ready now (a completed Store, an EMCY after a write) goes out at once
  const auto flush = [&] { bus.step(std::chrono::milliseconds(0)); };
  const auto index_sub = [&](std::array<std::uint8_t, 8>& d) {
    const auto& [index, sub] = g_entries[r.u16() % g_entries.size()];
    d[1] = static_cast<std::uint8_t>(index);
    d[2] = static_cast<std::uint8_t>(index >> 8);
    d[3] = sub;
  };
  const auto payload = [&](std::array<std::uint8_t, 8>& d, std::size_t from) {
    for (std::size_t i = from; i < 8; ++i) d[i] = r.byte();
  };

  while (!r.empty()) {
    const std::uint8_t op = r.byte();
    Client& c = (op & 0x80) ? b : a;
    std::array<std::uint8_t, 8> d{};
    const unsigned op_kind = (op & 0x3F) % 12;  // 0x40 and 0x80 are flags: a variant of the op, client B
    switch (op_kind) {
      case 0: c.feed(r.bytes()); break;
      case 1: {  // one SDO request: a command specifier of CiA 301 §7.2.4 with fuzzed flags
        static constexpr std::array<std::uint8_t, 12> k_base = {0x20, 0x00, 0x40, 0x60, 0xC0, 0x00,
                                                                0xC1, 0xA0, 0xA2, 0xA3, 0xA1, 0x80};
        static constexpr std::array<std::uint8_t, 12> k_flags = {0x0F, 0x1F, 0x00, 0x10, 0x06, 0xFF,
                                                                 0x1C, 0x04, 0x00, 0x00, 0x00, 0x00};
        const std::uint8_t kind = r.byte() % k_base.size();
        d[0] = static_cast<std::uint8_t>(k_base[kind] | (r.byte() & k_flags[kind]));
        index_sub(d);
        payload(d, (kind == 1 || kind == 5) ? 1 : 4);
        c.feed(sdo_line(d));
        break;
      }
      case 2: {  // expedited or segmented upload to the end (the client's side of §6.2/§6.3)
        d[0] = 0x40;
        index_sub(d);
        c.feed(sdo_line(d));
        const unsigned segments = r.byte() % 16;
        for (unsigned i = 0; i < segments; ++i) c.feed(sdo_line({static_cast<std::uint8_t>(0x60 | ((i & 1) << 4))}));
        break;
      }
      case 3: {  // segmented download of fuzzed bytes (size indicated), maybe with a wrong toggle
        const std::string_view bytes = r.bytes();
        d[0] = 0x21;
        index_sub(d);
        d[4] = static_cast<std::uint8_t>(bytes.size());
        c.feed(sdo_line(d));
        const bool bad_toggle = (op & 0x40) != 0;
        std::size_t at = 0;
        unsigned toggle = bad_toggle ? 1 : 0;
        do {
          std::array<std::uint8_t, 8> s{};
          const std::size_t n = std::min<std::size_t>(7, bytes.size() - at);
          for (std::size_t i = 0; i < n; ++i) s[1 + i] = static_cast<std::uint8_t>(bytes[at + i]);
          at += n;
          const bool last = at >= bytes.size();
          s[0] = static_cast<std::uint8_t>((toggle << 4) | ((7 - n) << 1) | (last ? 1 : 0));
          toggle ^= 1;
          c.feed(sdo_line(s));
        } while (at < bytes.size());
        break;
      }
      case 4: {  // block download with CRC (§6.4, §6.6); a fuzzed flag breaks the CRC or a seqno
        const std::string_view bytes = r.bytes();
        const std::uint8_t flaw = r.byte();
        d[0] = 0xC6;  // client CRC, size indicated
        index_sub(d);
        d[4] = static_cast<std::uint8_t>(bytes.size());
        c.feed(sdo_line(d));
        std::size_t at = 0;
        std::uint8_t seq = 1;
        do {
          std::array<std::uint8_t, 8> s{};
          const std::size_t n = std::min<std::size_t>(7, bytes.size() - at);
          for (std::size_t i = 0; i < n; ++i) s[1 + i] = static_cast<std::uint8_t>(bytes[at + i]);
          at += n;
          s[0] = static_cast<std::uint8_t>((flaw == 1 && seq == 2 ? seq + 1 : seq) | (at >= bytes.size() ? 0x80 : 0));
          ++seq;
          c.feed(sdo_line(s));
        } while (at < bytes.size());
        const std::size_t last_n = bytes.empty() ? 0 : ((bytes.size() - 1) % 7) + 1;
        std::uint16_t crc = canopen::crc16_ccitt(
            std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
        if (flaw == 2) crc ^= 1;
        std::array<std::uint8_t, 8> end{};
        end[0] = static_cast<std::uint8_t>(0xC1 | ((7 - last_n) << 2));
        end[1] = static_cast<std::uint8_t>(crc);
        end[2] = static_cast<std::uint8_t>(crc >> 8);
        c.feed(sdo_line(end));
        break;
      }
      case 5: {       // block upload (§6.5): initiate, start, acknowledge every sub-block, end
        d[0] = 0xA4;  // client CRC
        index_sub(d);
        d[4] = static_cast<std::uint8_t>(r.byte() % 128 + 1);  // blksize
        d[5] = r.byte();                                       // protocol switch threshold
        c.feed(sdo_line(d));
        c.feed(sdo_line({0xA3}));
        const unsigned acks = r.byte() % 8;
        for (unsigned i = 0; i < acks; ++i)
          c.feed(sdo_line({0xA2, r.byte(), static_cast<std::uint8_t>(r.byte() % 128)}));
        c.feed(sdo_line({0xA1}));
        break;
      }
      case 6: {  // NMT: start, stop, pre-operational, reset node, reset communication
        static constexpr std::array<std::uint8_t, 6> k_cs = {0x01, 0x02, 0x80, 0x81, 0x82, 0x00};
        c.feed(sdo_line({k_cs[r.byte() % k_cs.size()], static_cast<std::uint8_t>((r.byte() & 1) ? 50 : 0)}, 0x000, 2));
        break;
      }
      case 7: {  // SYNC, an RPDO, a guarding request, TIME, another node's SDO
        static constexpr std::array<std::uint16_t, 8> k_ids = {0x080, 0x232, 0x332, 0x432, 0x532, 0x100, 0x633, 0x732};
        const std::uint16_t id = k_ids[r.byte() % k_ids.size()];
        if (id == 0x732) {
          c.feed("r7321\r");
        } else {
          payload(d, 0);
          c.feed(sdo_line(d, id, static_cast<std::uint8_t>(r.byte() % 9)));
        }
        break;
      }
      case 8: drive_time.advance(r.byte() + 1u); break;
      case 9: drive_time.advance(r.byte() * 20u); break;  // past SDO timeouts and heartbeats
      case 10:
        drive.storage().complete((op & 0x40) == 0);
        drive.device().handle_events();
        break;
      default: {  // a command line of §3.4
        static constexpr std::array<const char*, 12> k_cmds = {"O\r", "L\r", "C\r",  "S4\r", "V\r",     "v\r",
                                                               "N\r", "F\r", "Z1\r", "Z0\r", "s031C\r", "\r"};
        c.feed(k_cmds[r.byte() % k_cmds.size()]);
        break;
      }
    }
    if (op_kind != 8 && op_kind != 9) drive_time.touch();  // the server's wake after a client's input
    flush();
    a.collect();
    b.collect();
  }

  while (drive.storage().pending() > 0) {
    drive.storage().complete(true);
    drive.device().handle_events();
    flush();
  }
  a.collect();
  b.collect();
  for (const Client* c : {&a, &b}) {
    const bool acks = drive.device().slcan_config().frame_ack != slcan::FrameAck::none;
    if (acks && c->replies != c->lines) {
      fuzz::fail("session answered " + std::to_string(c->replies) + " of " + std::to_string(c->lines) + " lines");
    }
    if (c->replies > c->lines) fuzz::fail("more replies than lines");
  }
  fuzz::check_dictionary(drive.od());
  return 0;
}
