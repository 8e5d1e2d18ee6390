// The drive's receiver of §4 (faulhaber.md), sans I/O: bytes and the simulated time of their arrival
// in, complete frames and dropped-frame diagnostics out, through a Sink, one at a time and in byte
// order — the caller handles each frame before the next byte is looked at, so a request that
// changes the CRC switch (0x2400.04 bit 23) or the node-id acts on the very next frame, however the
// bytes were split.
//
// Rules: wait for `S`; the next byte is L — L < 4 drops the `S` and scanning resumes at the byte
// after it; collect L + 2 bytes; a last byte other than `E` drops the frame and scanning resumes at
// the byte after its `S` (a stray `S` in noise does not swallow the next good frame); a wrong CRC
// (when Sink::check_crc() says so) drops the frame the same way [choice: a stray `S` whose L
// happens to end on an `E` must not swallow a good frame either]; more than `inter_byte_timeout`
// between two bytes of one frame drops the partial frame (noticed when the next byte arrives) and
// that byte starts afresh. Memory is fixed: one frame of at most 257 bytes, one rescan buffer of
// the same size, per-byte arrival times. Pure, single-threaded; `now` never goes back.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "protocols/faulhaber/frame.hpp"

namespace mcemu::faulhaber {

using Millis = std::chrono::milliseconds;

enum class DropReason : std::uint8_t { garbage, bad_length, bad_eof, bad_crc, timeout };
std::string_view to_string(DropReason r);  // "garbage before SOF", "L < 4", "no E", "bad CRC", "timeout"

struct Dropped {
  DropReason reason = DropReason::garbage;
  std::span<const std::uint8_t> bytes;  // the discarded bytes (garbage: the first 16 of the run)
  std::size_t count = 0;                // number of discarded bytes
};

class Receiver {
 public:
  static constexpr Millis k_default_timeout{50};
  static constexpr std::size_t k_garbage_kept = 16;

  class Sink {
   public:
    // A frame (view into the receiver's buffer: valid during the call only) and its wire bytes.
    virtual void on_frame(const FrameView& frame, std::span<const std::uint8_t> raw) = 0;
    virtual void on_dropped(const Dropped& dropped) = 0;
    // Asked once per delimited frame: true = its CRC must be right (0x2400.04 bit 23 clear).
    virtual bool check_crc() = 0;

   protected:
    ~Sink() = default;
  };

  explicit Receiver(Millis inter_byte_timeout = k_default_timeout) : timeout_(inter_byte_timeout) {}

  void feed(std::span<const std::uint8_t> bytes, Millis now, Sink& sink);
  // Discards a partial frame and the rescan buffer (connection closed).
  void reset();
  // Bytes of a partial frame held now (0 … 256).
  std::size_t partial() const { return len_; }

 private:
  void step(std::uint8_t b, Millis t, bool fresh, Sink& sink);
  void drain_rescan(Sink& sink);
  void complete(Sink& sink);
  void fail(DropReason reason, Sink& sink);
  void flush_garbage(Sink& sink);

  Millis timeout_;
  std::array<std::uint8_t, k_max_frame> buf_{};
  std::array<Millis, k_max_frame> times_{};
  std::size_t len_ = 0;
  // Bytes after a dropped frame's `S`, scanned again (with their arrival times) before new input.
  std::array<std::uint8_t, k_max_frame> rescan_{};
  std::array<Millis, k_max_frame> rescan_times_{};
  std::size_t rescan_pos_ = 0;
  std::size_t rescan_len_ = 0;
  std::array<std::uint8_t, k_garbage_kept> garbage_{};
  std::size_t garbage_count_ = 0;
};

}  // namespace mcemu::faulhaber
