#include "protocols/faulhaber/receiver.hpp"

#include <algorithm>

#include "protocols/faulhaber/crc.hpp"

namespace mcemu::faulhaber {

namespace {

// Moves a[from, from + n) to a[to, to + n); the ranges may overlap.
template <class Array>
void shift(Array& a, std::size_t from, std::size_t to, std::size_t n) {
  const auto first = a.begin() + static_cast<std::ptrdiff_t>(from);
  const auto last = first + static_cast<std::ptrdiff_t>(n);
  const auto dest = a.begin() + static_cast<std::ptrdiff_t>(to);
  if (to < from) {
    std::copy(first, last, dest);
  } else if (to > from) {
    std::copy_backward(first, last, dest + static_cast<std::ptrdiff_t>(n));
  }
}

}  // namespace

std::string_view to_string(DropReason r) {
  switch (r) {
    case DropReason::garbage: return "garbage before SOF";
    case DropReason::bad_length: return "L < 4";
    case DropReason::bad_eof: return "no E";
    case DropReason::bad_crc: return "bad CRC";
    case DropReason::timeout: return "timeout";
  }
  return "?";
}

void Receiver::feed(std::span<const std::uint8_t> bytes, Millis now, Sink& sink) {
  for (const std::uint8_t b : bytes) {
    step(b, now, true, sink);
    drain_rescan(sink);
  }
  flush_garbage(sink);
}

void Receiver::reset() {
  len_ = 0;
  rescan_pos_ = rescan_len_ = 0;
  garbage_count_ = 0;
}

void Receiver::drain_rescan(Sink& sink) {
  while (rescan_pos_ < rescan_len_) {
    const std::size_t i = rescan_pos_++;
    step(rescan_[i], rescan_times_[i], false, sink);
  }
}

void Receiver::step(std::uint8_t b, Millis t, bool fresh, Sink& sink) {
  if (len_ > 0 && t - times_[len_ - 1] > timeout_) {
    // A stale partial frame: its bytes are not scanned again (a frame inside them is as old).
    sink.on_dropped({DropReason::timeout, std::span<const std::uint8_t>(buf_.data(), len_), len_});
    len_ = 0;
  }
  if (len_ == 0) {
    if (b != k_sof) {
      // Bytes scanned again were already reported with the frame they belonged to.
      if (fresh) {
        if (garbage_count_ < k_garbage_kept) garbage_[garbage_count_] = b;
        ++garbage_count_;
      }
      return;
    }
    flush_garbage(sink);
  }
  buf_[len_] = b;
  times_[len_] = t;
  ++len_;
  if (len_ == 2 && buf_[1] < k_min_length) return fail(DropReason::bad_length, sink);
  if (len_ > 2 && len_ == static_cast<std::size_t>(buf_[1]) + 2) complete(sink);
}

void Receiver::complete(Sink& sink) {
  if (buf_[len_ - 1] != k_eof) return fail(DropReason::bad_eof, sink);
  const std::span<const std::uint8_t> raw(buf_.data(), len_);
  const std::size_t length = buf_[1];
  if (sink.check_crc() && crc8(raw.subspan(1, length - 1)) != buf_[length]) {
    // Scanned again after its S like a wrong E: an `S` in noise whose L happens to end on an `E`
    // must not swallow the good frame inside it either (§4 step 3's reason).
    return fail(DropReason::bad_crc, sink);
  }
  len_ = 0;  // the view below stays valid: nothing is written to buf_ before the next step()
  sink.on_frame(FrameView{buf_[2], buf_[3], raw.subspan(4, length - 4)}, raw);
}

void Receiver::fail(DropReason reason, Sink& sink) {
  sink.on_dropped({reason, std::span<const std::uint8_t>(buf_.data(), len_), len_});
  // Scan again from the byte after the `S`: the frame's other bytes, then what was still waiting
  // to be scanned again. Frame + waiting bytes never exceed one frame (257), so this fits.
  const std::size_t waiting = rescan_len_ - rescan_pos_;
  const std::size_t again = len_ - 1;
  shift(rescan_, rescan_pos_, again, waiting);
  shift(rescan_times_, rescan_pos_, again, waiting);
  std::copy_n(buf_.begin() + 1, again, rescan_.begin());
  std::copy_n(times_.begin() + 1, again, rescan_times_.begin());
  rescan_pos_ = 0;
  rescan_len_ = again + waiting;
  len_ = 0;
}

void Receiver::flush_garbage(Sink& sink) {
  if (garbage_count_ == 0) return;
  const std::size_t kept = std::min(garbage_count_, k_garbage_kept);
  sink.on_dropped({DropReason::garbage, std::span<const std::uint8_t>(garbage_.data(), kept), garbage_count_});
  garbage_count_ = 0;
}

}  // namespace mcemu::faulhaber
