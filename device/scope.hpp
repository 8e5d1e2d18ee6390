// The scope sampler of web.md §5.3 and §8.7: every 5 ms of drive time one sample of position
// 6064h, velocity 606Ch, current 6078h, target 607Ah and statusword 6041h, in a ring of 60 s.
//
// PURE and single-threaded. Contract: on_step() runs after every drive step with the drive time
// after the step; it samples when that time is a multiple of 5 ms. Samples are contiguous (sample k
// of a block is at t0 + 5·k): a gap in the sample times (a step skipped by the caller) or drive time
// going backwards (a power cycle that restarts the clock) starts the ring anew.
// since_ms() answers GET /api/v1/scope?sinceMs=T; take_new() returns the samples since its
// previous call (the WebSocket "scope" message, once per period, shared by all clients).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "drive/od/dictionary.hpp"

namespace mcemu::device {

struct ScopeSample {
  std::int32_t pos = 0;
  std::int32_t vel = 0;
  std::int32_t cur = 0;
  std::int32_t target = 0;
  std::uint16_t sw = 0;
  bool operator==(const ScopeSample&) const = default;
};

struct ScopeBlock {
  std::uint64_t sample_ms = 5;
  std::uint64_t t0 = 0;  // drive time of the first sample (of the next one when empty)
  std::vector<ScopeSample> samples;
};

class Scope {
 public:
  static constexpr std::uint64_t k_sample_ms = 5;
  static constexpr std::uint64_t k_window_ms = 60000;
  static constexpr std::size_t k_capacity = k_window_ms / k_sample_ms;

  // After every drive step: samples the objects when time_ms is a multiple of k_sample_ms.
  void on_step(std::uint64_t time_ms, const od::ObjectDictionary& od);
  // One sample at time_ms (tests; on_step() reads the objects and calls this).
  void add(std::uint64_t time_ms, const ScopeSample& s) { add_run(time_ms, 1, s); }
  // `count` equal samples from time_ms on, every k_sample_ms: what a quiet stretch of the drive
  // leaves (the objects do not change). O(1): the ring keeps runs of equal samples.
  void add_run(std::uint64_t time_ms, std::uint64_t count, const ScopeSample& s);
  // The objects' sample now (what on_step() would add).
  // The entries are looked up once per dictionary (a drive's entries never move) and then read by
  // handle: a moving fleet samples every 5 ms per drive.
  ScopeSample sample_of(const od::ObjectDictionary& od);

  // Samples from the first sample time ≥ t (at most the ring, 60 s).
  ScopeBlock since_ms(std::uint64_t t) const;
  // Samples added since the previous call (all of the ring on the first call).
  ScopeBlock take_new();

  std::size_t size() const { return total_; }
  // Bytes the encoded runs take (tests, benchmarks): a moving drive's 60 s take ~5 bytes a sample.
  std::size_t encoded_bytes() const { return bytes_.size(); }

 private:
  struct Run {
    ScopeSample sample;
    std::uint32_t count = 0;  // ≤ 2 · k_capacity before the ring is trimmed
  };
  static_assert(2 * k_capacity <= UINT32_MAX);
  // Reads the encoded runs from the oldest on; `prev` is the sample of the run before.
  struct Reader {
    std::deque<std::uint8_t>::const_iterator at;
    ScopeSample prev;
    std::size_t bytes = 0;  // of the last run read
    Run next();
  };
  static void encode(std::deque<std::uint8_t>& out, const ScopeSample& prev, const Run& run);
  void push_run(const ScopeSample& s, std::uint32_t n);
  void drop_oldest(std::size_t n);
  ScopeBlock block_from(std::size_t first) const;
  std::uint64_t time_of(std::size_t i) const { return first_ms_ + i * k_sample_ms; }

  const od::ObjectDictionary* source_ = nullptr;        // the dictionary handles_ belong to
  std::array<std::optional<od::Handle>, 5> handles_{};  // 6064h, 606Ch, 6078h, 607Ah, 6041h
  // The ring: runs of equal samples, oldest first, total_ samples in all. A moving drive adds one
  // run per sample (each differs), 12 000 in 60 s, so all runs but the newest are kept as bytes:
  // which fields differ from the run before (one byte) and their differences and the count as
  // varints, ~5 bytes instead of 24. The newest run stays as it is, so that an equal sample only
  // counts up.
  // Samples and bytes that left the window since the ring started anew, so that a position in
  // the ring can be named across drops: the oldest encoded run starts at sample dropped_ -
  // oldest_dropped_ and at byte erased_.
  std::uint64_t dropped_ = 0;
  std::uint64_t erased_ = 0;
  // Where the last read began (the run it began in): the next read of newer samples — a WebSocket
  // scope period, ?sinceMs — starts there instead of decoding the window from its oldest run.
  struct Cursor {
    std::uint64_t run_start = 0;  // the run's first sample (dropped_ counting)
    std::uint64_t byte = 0;       // its first byte (erased_ counting)
    ScopeSample prev;             // the sample of the run before it
  };
  mutable std::optional<Cursor> cursor_;
  std::deque<std::uint8_t> bytes_;
  ScopeSample base_;                  // the sample of the run before the oldest encoded one
  ScopeSample last_encoded_;          // of the newest encoded run (base_ while there is none)
  std::uint32_t oldest_dropped_ = 0;  // samples of the oldest encoded run already out of the window
  std::optional<Run> newest_;
  std::size_t total_ = 0;
  std::uint64_t first_ms_ = 0;     // time of the oldest sample
  std::uint64_t next_new_ms_ = 0;  // first sample time take_new() has not returned
};

// {"sampleMs": 5, "t0": …, "pos": […], "vel": […], "cur": […], "target": […], "sw": […]}
nlohmann::json scope_json(const ScopeBlock& b);
// The WebSocket message of web.md §10.3: scope_json() plus "type": "scope".
std::string scope_message(const ScopeBlock& b);

}  // namespace mcemu::device
