// The real drive behind the session fuzzers: preset, dictionary, drive core, I/O functions and the
// persistence service (Store/Restore hooks) with an in-memory storage whose writes complete when
// the fuzz input says so, in order, successfully or not. Built fresh for every input, so a crash
// reproduces from its input alone. Also the fuzzers' common invariants: the dictionary is never
// corrupted (every stored value has its entry's kind and type range).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "drive/drive_core.hpp"
#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "iofunc/io_functions.hpp"
#include "persistence/service.hpp"
#include "persistence/state_document.hpp"

namespace mcemu::fuzz {

// A finding: print it and abort, so that libFuzzer (and the replay runner) report the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

// Storage whose writes wait until complete() — the worker thread of the real server, in order.
class MemoryStorage final : public persistence::Storage {
 public:
  void write_state(std::string contents, Completion done) override {
    last_ = std::move(contents);
    queue_.push_back(std::move(done));
  }
  // Completes the oldest pending write; `ok` false = the write failed (disk full).
  void complete(bool ok) {
    if (queue_.empty()) return;
    auto done = std::move(queue_.front());
    queue_.pop_front();
    if (done) done(ok ? std::nullopt : std::optional<std::string>("fuzz: write failed"));
  }
  std::size_t pending() const { return queue_.size(); }
  const std::string& last() const { return last_; }

 private:
  std::deque<Completion> queue_;
  std::string last_;
};

struct DriveBundle {
  explicit DriveBundle(std::string_view model = "MC349")
      : preset(*model::find_preset(model)),
        od(preset),
        core(preset, od),
        io(od, core),
        persistence(od, preset.name, "fuzz", persistence::snapshot(od), std::nullopt, storage, hooks()) {
    io.power_on();
  }

  // One 1 ms step of the server's loop (iofunc steps the core).
  void step() {
    io.step();
    drain();
  }
  // The core's events go to on_event (the server hands EMCYs to the CANopen node).
  void drain() {
    (void)io.drain_diagnostics();
    for (const auto& e : core.drain_events()) {
      if (on_event) on_event(e);
    }
  }

  persistence::ServiceHooks hooks() {
    persistence::ServiceHooks h;
    h.now_utc = [] { return std::string("2026-01-15T10:15:02Z"); };
    h.operation_enabled = [this] { return core.state() == core::PdsState::operation_enabled; };
    h.home_offset_inc = [this] { return core.home_offset_inc(); };
    h.after_restore = [this] {
      io.after_bulk_load();
      if (after_restore) after_restore();
    };
    return h;
  }

  std::function<void(const core::Event&)> on_event;
  std::function<void()> after_restore;  // e.g. the CANopen node's reload()
  model::ModelPreset preset;
  od::ObjectDictionary od;
  core::DriveCore core;
  iofunc::IoFunctions io;
  MemoryStorage storage;
  persistence::Service persistence;
};

// Every stored value has the kind and range of its entry's data type (the checks every write path
// makes), so no input can leave the dictionary in a state a write could not have produced.
inline void check_dictionary(const od::ObjectDictionary& od) {
  od.for_each([](const od::EntryInfo& info, const od::Value& v) {
    const auto converted = od::convert_for_write(info, v);
    if (!converted) {
      fail("entry " + std::to_string(info.index) + "." + std::to_string(info.sub) + " (" + std::string(info.name) +
           ") holds a value its type refuses");
    }
  });
}

// Reads little input-driven records: [op][len][payload…], each field clamped to what is left.
class Records {
 public:
  Records(const std::uint8_t* data, std::size_t size) : p_(data), end_(data + size) {}
  bool empty() const { return p_ >= end_; }
  std::uint8_t byte() { return p_ < end_ ? *p_++ : 0; }
  std::uint16_t u16() {
    const std::uint16_t lo = byte();
    return static_cast<std::uint16_t>(lo | (byte() << 8));
  }
  // A length-prefixed byte string (length byte, then up to that many bytes).
  std::string_view bytes() {
    const std::size_t want = byte();
    const std::size_t n = std::min<std::size_t>(want, static_cast<std::size_t>(end_ - p_));
    std::string_view s(reinterpret_cast<const char*>(p_), n);
    p_ += n;
    return s;
  }

 private:
  const std::uint8_t* p_;
  const std::uint8_t* end_;
};

}  // namespace mcemu::fuzz
