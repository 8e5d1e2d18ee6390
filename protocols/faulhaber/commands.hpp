// The command dispatcher of the binary protocol (faulhaber.md §5): one table row per command code,
// each handler turning one request addressed to this drive into its response, through the object
// dictionary only (origin `sdo`). Pure, single-threaded.
//
// Rows: 0x00 reset node (no response; Outcome::reset_node asks the owner for a device reset),
// 0x01 SDO read, 0x02 SDO write, 0x03 abort request (answered with the 7-byte 0x03 frame),
// 0x04 controlword (an SDO write of 6040h.00; error byte 0 = written, 1 = refused). Every other
// code — 0x05, 0x06 logging, 0x07, 0x08 … 0x0D block transfers, undefined — answers the error
// response 0x05040001 with index/sub-index from data bytes 0 … 2 (0000.00 when fewer than 3).
// Layout errors [choice]: a read with other than 3 data bytes, a write with fewer than 3 and an
// abort request with other than 7 answer 0x05040001 (index/sub-index as above); a write's value
// length is checked by the dictionary (write_bytes, length indicated: longer than the entry →
// 0x06070012, shorter → 0x06070013); a controlword of other than 2 bytes is the same 6040h.00
// write, so it is refused with error byte 1 by that rule.
// Responses carry `node_id` — the id in use when the request arrived — so a write of 0x2400.03 is
// answered with the old id. Read values are the entry's size; a string is cut at 58 bytes
// (COMM Tab. 2; no mcemu object is longer).
#pragma once

#include <cstdint>
#include <functional>

#include "drive/od/abort_code.hpp"
#include "drive/od/dictionary.hpp"
#include "protocols/faulhaber/frame.hpp"

namespace mcemu::faulhaber {

struct Outcome {
  enum class Kind : std::uint8_t {
    respond,  // `response` is the answer
    none,     // no answer (reset node)
    pending,  // the dictionary answered `pending` (Store/Restore): the answer comes through Later
  };
  Kind kind = Kind::respond;
  Frame response;
  bool reset_node = false;
  od::AbortCode code = od::AbortCode::none;  // the dictionary's result behind the answer (trace)
};

class Commands {
 public:
  // Receives the answer of a pending write, once, later (on the event-loop thread).
  using Later = std::function<void(Frame response, od::AbortCode code)>;

  explicit Commands(od::ObjectDictionary& od) : od_(od) {}

  Outcome handle(const FrameView& request, std::uint8_t node_id, const Later& later) const;
  // The name of a command code's row ("SDO read", …; "unsupported" for the rest).
  static const char* name(std::uint8_t code);

 private:
  od::ObjectDictionary& od_;
};

}  // namespace mcemu::faulhaber
