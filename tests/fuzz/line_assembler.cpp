// Fuzz target: the CR/LF line assembler shared by RefGo and SLCAN (protocols/line, refgo.md §2.2,
// slcan-canopen.md §3.2), with both protocols' byte filters and maximum lengths.
//
// Input: the first byte picks the filter and how the rest is cut into feed() calls (the next bytes
// give the chunk lengths); the rest is the stream. Oracles: the result does not depend on the
// split (rule 7 of §3.2, Beast's parsegrind); no line is longer than the maximum; only an over-long
// line is truncated; no line holds CR or LF, nor (RefGo) a control byte.
#include "protocols/line/line_assembler.hpp"

#include <string>
#include <vector>

#include "protocols/refgo/codec.hpp"
#include "tests/fuzz/drive_bundle.hpp"

namespace {

using namespace mcemu;

bool same(const std::vector<line::Line>& x, const std::vector<line::Line>& y) {
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i].text != y[i].text || x[i].overlong != y[i].overlong) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool refgo = (data[0] & 1) != 0;
  const std::size_t max = refgo ? refgo::k_max_line : 64;
  const line::ByteFilter filter = refgo ? refgo::filter_byte : line::keep_all;
  const std::string_view stream(reinterpret_cast<const char*>(data + 1), size - 1);

  line::LineAssembler whole(max, filter);
  const auto expected = whole.feed(stream);

  line::LineAssembler split(max, filter);
  std::vector<line::Line> got;
  std::size_t at = 0;
  std::size_t k = 0;
  while (at < stream.size()) {
    // chunk lengths 1…16 taken from the stream itself, so the fuzzer controls the cut
    const std::size_t n =
        std::min<std::size_t>(stream.size() - at, (static_cast<unsigned char>(stream[k++ % stream.size()]) % 16) + 1);
    split.feed(stream.substr(at, n), got);
    at += n;
  }
  if (!same(expected, got)) mcemu::fuzz::fail("the split of the stream changed the lines");
  if (whole.has_partial() != split.has_partial()) mcemu::fuzz::fail("the split changed the unterminated rest");

  for (const auto& l : expected) {
    if (l.text.size() > max) mcemu::fuzz::fail("line longer than the maximum");
    if (!l.overlong && l.text.size() == max + 1) mcemu::fuzz::fail("truncated without overlong");
    for (const unsigned char c : l.text) {
      if (c == '\r' || c == '\n') mcemu::fuzz::fail("line end inside a line");
      if (refgo && (c < 0x20 || c == 0x7F)) mcemu::fuzz::fail("control byte kept by the RefGo filter");
    }
  }
  return 0;
}
