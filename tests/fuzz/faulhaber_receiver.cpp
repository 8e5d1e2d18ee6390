// Fuzz target: the FAULHABER binary-protocol receiver (faulhaber.md §4) alone.
//
// Input: one flag byte (bit 0: CRC check on), then records [gap][len][bytes…]: the bytes arrive
// `gap` ms after the previous record (gaps above 50 ms end a partial frame).
// Oracles beyond "no crash, no sanitizer report": the frames equal those of a reference scan of the
// whole input written straight from §4 (index-based, with per-byte arrival times); feeding the same
// bytes one at a time at the same times gives the same frames and drops; every frame is well
// delimited (L ≥ 4, L + 2 bytes, `S` … `E`, correct CRC when checked) and its view matches its raw
// bytes; the receiver never holds more than one frame.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "protocols/faulhaber/crc.hpp"
#include "protocols/faulhaber/receiver.hpp"

namespace {

using namespace mcemu::faulhaber;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

struct Recorder final : Receiver::Sink {
  bool crc = true;
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<std::pair<DropReason, std::vector<std::uint8_t>>> drops;  // garbage excepted
  std::size_t garbage = 0;

  void on_frame(const FrameView& f, std::span<const std::uint8_t> raw) override {
    if (raw.size() < 6 || raw[0] != k_sof || raw.back() != k_eof) fail("frame not delimited by S … E");
    if (raw[1] < k_min_length || raw.size() != static_cast<std::size_t>(raw[1]) + 2) fail("frame length ≠ L + 2");
    if (crc && crc8(raw.subspan(1, raw[1] - 1)) != raw[raw[1]]) fail("frame with a wrong CRC accepted");
    if (f.node != raw[2] || f.command != raw[3] || f.data.size() != raw[1] - 4u || f.data.data() != raw.data() + 4) {
      fail("frame view does not match its bytes");
    }
    frames.emplace_back(raw.begin(), raw.end());
  }
  void on_dropped(const Dropped& d) override {
    if (d.reason == DropReason::garbage) {
      if (d.bytes.size() > Receiver::k_garbage_kept || d.bytes.size() > d.count || d.count == 0) fail("garbage drop");
      garbage += d.count;
      return;
    }
    if (d.bytes.size() != d.count || d.bytes.empty() || d.bytes[0] != k_sof) fail("dropped frame bytes");
    drops.emplace_back(d.reason, std::vector<std::uint8_t>(d.bytes.begin(), d.bytes.end()));
  }
  bool check_crc() override { return crc; }
};

// §4 as an index scan over the whole input (t[i]: arrival time of byte i).
std::vector<std::vector<std::uint8_t>> reference(const std::vector<std::uint8_t>& in, const std::vector<Millis>& t,
                                                 bool crc) {
  std::vector<std::vector<std::uint8_t>> frames;
  const std::size_t n = in.size();
  std::size_t i = 0;
  while (i < n) {
    if (in[i] != k_sof) {
      ++i;
      continue;
    }
    // Collect byte by byte from i + 1, as the receiver does: a gap ends the partial frame and the
    // byte after the gap starts afresh; L < 4, a missing E or a bad CRC resume after the S.
    std::size_t j = i + 1;
    bool restart_at_j = false;
    std::size_t need = 0;  // total frame length once L is known
    bool partial = false;
    bool failed = false;
    while (true) {
      if (j >= n) {
        partial = true;
        break;
      }
      if (t[j] - t[j - 1] > Receiver::k_default_timeout) {
        restart_at_j = true;
        break;
      }
      if (j == i + 1) {
        if (in[j] < k_min_length) {
          failed = true;
          break;
        }
        need = static_cast<std::size_t>(in[j]) + 2;
      }
      if (j + 1 - i == need) break;
      ++j;
    }
    if (partial) break;
    if (restart_at_j) {
      i = j;
      continue;
    }
    if (failed) {
      ++i;
      continue;
    }
    const std::size_t end = i + need;  // one past the E
    const bool eof_ok = in[end - 1] == k_eof;
    const bool crc_ok =
        !crc || crc8(std::span<const std::uint8_t>(in).subspan(i + 1, in[i + 1] - 1)) == in[i + in[i + 1]];
    if (!eof_ok || !crc_ok) {
      ++i;
      continue;
    }
    frames.emplace_back(in.begin() + static_cast<std::ptrdiff_t>(i), in.begin() + static_cast<std::ptrdiff_t>(end));
    i = end;
  }
  return frames;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool crc = (data[0] & 1) != 0;
  // records → chunks with arrival times
  std::vector<std::pair<Millis, std::vector<std::uint8_t>>> chunks;
  std::vector<std::uint8_t> all;
  std::vector<Millis> times;
  Millis now{0};
  std::size_t p = 1;
  while (p < size) {
    now += Millis(data[p++] % 64);
    const std::size_t want = p < size ? data[p++] : 0;
    const std::size_t n = std::min(want, size - p);
    chunks.emplace_back(now, std::vector<std::uint8_t>(data + p, data + p + n));
    for (std::size_t k = 0; k < n; ++k) times.push_back(now);
    all.insert(all.end(), data + p, data + p + n);
    p += n;
  }

  Recorder chunked;
  chunked.crc = crc;
  Receiver a;
  for (const auto& [t, bytes] : chunks) {
    a.feed(bytes, t, chunked);
    if (a.partial() >= k_max_frame) fail("receiver holds more than one frame");
  }

  Recorder single;
  single.crc = crc;
  Receiver b;
  for (std::size_t k = 0; k < all.size(); ++k) b.feed(std::span(all).subspan(k, 1), times[k], single);

  if (chunked.frames != single.frames) fail("frames depend on how the bytes are split");
  if (chunked.drops != single.drops) fail("drops depend on how the bytes are split");
  if (chunked.garbage != single.garbage) fail("garbage count depends on how the bytes are split");
  if (a.partial() != b.partial()) fail("partial frame depends on how the bytes are split");
  if (chunked.frames != reference(all, times, crc)) fail("frames differ from the reference scan of §4");
  return 0;
}
