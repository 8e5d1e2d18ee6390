// Cuts a TCP byte stream into lines for the line-oriented protocols (RefGo, SLCAN).
//
// Rules shared by refgo.md §2.2 and slcan-canopen.md §3.2: CR ends a line; LF ends a line too,
// except an LF whose preceding byte in the stream is a CR (also across feed() calls), which is
// dropped; "\n\r" is two line ends. Each protocol supplies a byte filter (RefGo replaces TAB and
// drops other control bytes; SLCAN keeps every byte) and a maximum length counted after filtering.
// Bytes beyond the maximum are discarded up to the next line end and the line is reported as
// over-long; memory stays bounded even if no line end ever comes. Pure; the split of the input into
// feed() calls never changes the result.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace mcemu::line {

struct Line {
  std::string text;       // filtered bytes, without the terminator (truncated if over-long)
  bool overlong = false;  // more than max_length bytes arrived before the terminator
  // The bytes as received, unfiltered, with the terminator (CR or LF) — for the trace. At most
  // max_length + 1 bytes are kept: an over-long line keeps its beginning.
  std::string raw;
};

// Returns the byte to keep, or -1 to drop it. Never called for CR or LF.
using ByteFilter = int (*)(unsigned char);

inline int keep_all(unsigned char c) { return c; }

class LineAssembler {
 public:
  LineAssembler(std::size_t max_length, ByteFilter filter) : max_length_(max_length), filter_(filter) {}

  // Appends every line completed by `bytes` to `out`; keeps the unterminated rest.
  void feed(std::string_view bytes, std::vector<Line>& out);
  std::vector<Line> feed(std::string_view bytes) {
    std::vector<Line> out;
    feed(bytes, out);
    return out;
  }
  // Bytes of the current, unterminated line (discarded when the peer closes, refgo.md §1.5).
  bool has_partial() const { return !current_.text.empty() || current_.overlong; }
  void reset();

 private:
  std::size_t max_length_;
  ByteFilter filter_;
  Line current_;
  bool last_was_cr_ = false;
};

}  // namespace mcemu::line
