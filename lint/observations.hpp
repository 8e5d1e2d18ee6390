// The observations the master lint is fed (docs/lint.md §2): plain values a drive bundle produces
// at the places it already traces — dictionary writes, core events, CANopen frames, protocol
// requests and replies, scripts, flash writes. Each carries the drive time in ms (DriveCore's
// time_ms(); it restarts at 0 on a power cycle, which the engine handles) and, where there is one,
// the connection id of the trace (0 = none) and the writer's origin.
//
// Contract: values only, nothing here reads the drive. Producers call lint::Engine::observe()
// with them on the event-loop thread, in the order things happened.
#pragma once

#include <cstdint>

#include "drive/events.hpp"
#include "drive/od/abort_code.hpp"
#include "drive/od/types.hpp"

namespace mcemu::lint {

using Ms = std::uint64_t;    // drive time, ms
using Conn = std::uint64_t;  // the trace's connection id; 0 = none

// One write to the object dictionary (write() or write_bytes()) with its result; the drive's
// statusword and mode display read right after it returned. Producer: a write tap of the
// dictionary. Writes by origin `internal` may be fed (they update the lint's view) or skipped.
struct OdWrite {
  Ms time = 0;
  Conn conn = 0;
  od::Origin origin = od::Origin::internal;
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::int64_t value = 0;                      // numbers; 0 for strings
  od::AbortCode result = od::AbortCode::none;  // none and pending are accepted
  std::uint16_t statusword_after = 0;          // 6041h after the write
  std::int8_t mode_after = 0;                  // 6061h after the write
  bool helper = false;  // one write of a helper's sequence (drive-core.md §12): master rules skip it
};

// A core event as the bundle's hand-off drains it (drive-core.md §13). The lint uses
// StatuswordChanged and ModeDisplayChanged to follow the drive between writes.
struct CoreEvent {
  Ms time = 0;
  const core::Event& event;
};

// The drive powered on (start, power cycle, NMT reset node): the lint forgets what it knew about
// the drive and the connections. Values read from the dictionary after the core's power_on().
struct PowerOn {
  Ms time = 0;
  std::uint16_t statusword = 0;      // 6041h
  std::uint16_t controlword = 0;     // 6040h (power_on() writes 0)
  std::int8_t mode = 0;              // 6060h
  std::int64_t target_velocity = 0;  // 60FFh (0 where the model has none)
};

// NMT states, with the values of canopen::NmtState (a static_cast maps them).
enum class Nmt : std::uint8_t { initialising = 0x00, stopped = 0x04, operational = 0x05, pre_operational = 0x7F };

// The CANopen node's NMT state changed (reset, boot-up, NMT command, life guarding reaction).
// Producer: the CAN bus, comparing node().state() around each call into the node.
struct NmtChange {
  Ms time = 0;
  Nmt from = Nmt::initialising;
  Nmt to = Nmt::initialising;
};

enum class CanKind : std::uint8_t { nmt, sync, sdo, guarding, rpdo, other };

// A frame a CAN client sent to the node, before the node processes it. Producer: the CAN bus;
// lint::classify_can_frame() (canopen_view.hpp) fills kind, rpdo, motion and life_time_ms.
struct CanRequest {
  Ms time = 0;
  Conn conn = 0;
  CanKind kind = CanKind::other;
  std::uint8_t byte0 = 0;          // SDO: the command byte of the request
  std::uint8_t rpdo = 0;           // RPDO: 1…4
  bool motion = false;             // RPDO: its mapping writes 6040h, 607Ah or 60FFh
  std::uint32_t life_time_ms = 0;  // RPDO: 100Ch × 100Dh while 1017h = 0, else 0 (life guarding off)
};

// The node sent an SDO response or abort (COB 0x580 + node-id). Producer: the CAN bus.
struct SdoAnswer {
  Ms time = 0;
  std::uint8_t byte0 = 0;
};

// A write to a PDO mapping object 1600h–1603h / 1A00h–1A03h and whether its PDO was valid (COB-ID
// bit 31 = 0) at the time. Producer: lint::pdo_mapping_write() in the dictionary write tap.
struct PdoMappingWrite {
  Ms time = 0;
  Conn conn = 0;
  od::Origin origin = od::Origin::sdo;
  std::uint16_t mapping_index = 0;
  std::uint8_t sub = 0;
  bool pdo_valid = false;
  od::AbortCode result = od::AbortCode::none;
};

enum class Link : std::uint8_t { refgo, faulhaber };

// One request of a line protocol, as it arrives (before it runs). `chunk` identifies the read
// (receive() call) it arrived in — requests of one read were all sent before any reply to them;
// 0 = unknown. `expects_reply` = false for a line only a script gets (refgo.md §5) and the like.
// Producer: the RefGo session observer (`received`), the FAULHABER port's rx trace.
struct ProtocolRequest {
  Ms time = 0;
  Link link = Link::refgo;
  Conn conn = 0;
  std::uint64_t chunk = 0;
  bool expects_reply = true;
};

enum class ReplyKind : std::uint8_t {
  response,      // the reply to this connection's oldest unanswered request, as sent
  none,          // that request gets no reply (ignored frame, reset node)
  notification,  // a FAULHABER statusword notification, to every connection (conn 0)
};

// Producer: the reply sink (RefGo, after transport gates), the FAULHABER port's tx trace.
struct ProtocolReply {
  Ms time = 0;
  Link link = Link::refgo;
  Conn conn = 0;
  ReplyKind kind = ReplyKind::response;
};

// A connection closed (optional: frees its slot early).
struct ConnectionClosed {
  Conn conn = 0;
};

enum class ScriptKind : std::uint8_t { code, basic };

// A script has run this many statements (MC BASIC) or mcdrive/refgo calls (MovingCap CODE) since
// it last waited (sleep, DELAY, a blocking read with a timeout). A producer reports it when it
// likes (e.g. once per drive step while the count grows); a smaller count means it waited.
struct ScriptLoop {
  Ms time = 0;
  ScriptKind script = ScriptKind::code;
  std::uint32_t statements_without_wait = 0;
};

enum class FlashKind : std::uint8_t { parameters, motor, factory_reset, program };

// A write to the drive's non-volatile memory that is not a dictionary write (an MC BASIC SAVE).
// Stores through 1010h, 1011h and 3010h.01 the engine takes from OdWrite itself.
struct FlashWrite {
  Ms time = 0;
  Conn conn = 0;
  od::Origin origin = od::Origin::script;
  FlashKind kind = FlashKind::program;
};

}  // namespace mcemu::lint
