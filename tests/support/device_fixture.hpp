// The one test fixture of mcemu (issue 23): a whole drive bundle (device/device.hpp) in virtual
// time, for unit tests, fuzz targets and benchmarks alike. The state file is written to memory
// (MemoryStorage: writes complete when the test says so, in order, successfully or not); the wall
// clock of the trace is fixed at 2026-01-15T10:15:02.123Z; core events are kept for the test.
//
// Usage: DeviceFixture d;                       // MC349, powered on, drive time 0
//        DeviceFixture d("MCFLAT", {{"objects", {{"6083.00", 2000}}}});
//        d.W(0x6040, 0, 6); d.step(10); d.R(0x6041);
// Three depths of a step, for tests of one layer: step() is the bundle's (the drive and every part:
// fault expiry, scope, RefGo programs, event hand-off, CANopen bus); step_drive() is the drive
// alone (the I/O functions, which step the core; nothing is drained); core().step() is the core
// alone. A test that steps less than the bundle drains the core's events itself.
// A FAULHABER preset builds its own personality's bundle: io() and refgo() are MovingCap only, and
// step_drive() steps the core itself (such a drive has no I/O functions).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "device/config_image.hpp"
#include "device/device.hpp"
#include "device/plant_settings.hpp"

namespace mcemu::testing {

// Storage whose writes wait until complete() — the worker thread of the real server, in order.
class MemoryStorage final : public persistence::Storage {
 public:
  void write_state(std::string contents, Completion done) override {
    last_ = std::move(contents);
    queue_.push_back(std::move(done));
    if (auto_complete_) complete(true);
  }
  // Every write completes successfully at once (a disk that is never slow).
  void set_auto_complete(bool on) { auto_complete_ = on; }
  // Completes the oldest pending write; `ok` false = the write failed (disk full).
  void complete(bool ok = true) {
    if (queue_.empty()) return;
    auto done = std::move(queue_.front());
    queue_.pop_front();
    if (done) done(ok ? std::nullopt : std::optional<std::string>("test: write failed"));
  }
  void complete_all(bool ok = true) {
    while (!queue_.empty()) complete(ok);
  }
  std::size_t pending() const { return queue_.size(); }
  const std::string& last() const { return last_; }

 private:
  std::deque<Completion> queue_;
  std::string last_;
  bool auto_complete_ = false;
};

inline constexpr std::int64_t k_fixture_unix_ms = 1768472102123;  // 2026-01-15T10:15:02.123Z

struct DeviceOptions {
  nlohmann::json config = nlohmann::json::object();
  std::optional<core::PlantConfig> plant;  // instead of the config's "plant"/"homing"
  bool keep_events = true;                 // collect the core events in `events`
  bool power_on = true;                    // false: the core waits for the test's power_on()
};

class DeviceFixture {
 public:
  explicit DeviceFixture(std::string model = "MC349", DeviceOptions options = {}) { build(model, std::move(options)); }
  DeviceFixture(std::string model, nlohmann::json config) : DeviceFixture(std::move(model), options_of(config)) {}
  DeviceFixture(const DeviceFixture&) = delete;
  DeviceFixture& operator=(const DeviceFixture&) = delete;

  device::Device& device() { return *device_; }
  od::ObjectDictionary& od() { return device_->od(); }
  const od::ObjectDictionary& od() const { return device_->od(); }
  core::DriveCore& core() { return device_->core(); }
  iofunc::IoFunctions& io() { return *device_->io(); }
  refgo::Interpreter& refgo() { return *device_->refgo(); }
  const model::ModelPreset& preset() const { return device_->preset(); }
  MemoryStorage& storage() { return storage_; }

  // The bundle's full 1 ms step (I/O functions, core, then every part), n times.
  void step(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      device_->step();
    }
  }
  // The drive alone, n times: the I/O functions (which step the core), no parts, no event hand-off.
  void step_drive(std::uint64_t n = 1) {
    for (std::uint64_t i = 0; i < n; ++i) {
      if (auto* io = device_->io()) {
        io->step();
      } else {
        device_->core().step();
      }
    }
  }
  // Steps until pred() holds; returns the steps taken, or max_ms + 1.
  template <typename Pred>
  std::uint64_t step_until(Pred pred, std::uint64_t max_ms) {
    for (std::uint64_t i = 1; i <= max_ms; ++i) {
      step();
      if (pred()) return i;
    }
    return max_ms + 1;
  }
  // A write with the given origin (SDO by default), then the event hand-off as after a request.
  od::AbortCode write(std::uint16_t index, std::uint8_t sub, od::Value value, od::Origin origin = od::Origin::sdo) {
    const auto c = od().write(index, sub, value, origin);
    device_->handle_events();
    device_->steps().touch();
    return c;
  }
  od::AbortCode W(std::uint16_t index, std::uint8_t sub, std::int64_t value, od::Origin origin = od::Origin::sdo) {
    return write(index, sub, od::Value{value}, origin);
  }
  std::int64_t R(std::uint16_t index, std::uint8_t sub = 0) const {
    const auto r = od().read_number(index, sub);
    return r ? *r : 0;
  }
  std::uint16_t sw() const { return static_cast<std::uint16_t>(R(0x6041)); }
  // Removes the Store/Restore hooks of the persistence service (1010h, 1011h .01–.03), for tests
  // that install their own.
  void release_store_hooks() {
    for (std::uint8_t sub = 1; sub <= 3; ++sub) {
      od().on_write(0x1010, sub, {});
      od().on_write(0x1011, sub, {});
    }
  }

  std::vector<core::Event> events;                   // every core event drained so far (keep_events)
  std::vector<std::string> notes;                    // the UDP emulator notes the bundle asked for
  std::function<void(const core::Event&)> on_event;  // called for every drained core event
  std::function<void(const std::string&)> on_log;    // the bundle's log lines (I/O diagnostics, …)
  std::function<void(const std::string&)> on_note;   // the bundle's UDP emulator notes

 private:
  static DeviceOptions options_of(nlohmann::json config) {
    DeviceOptions o;
    o.config = std::move(config);
    return o;
  }
  void build(const std::string& model, DeviceOptions options) {
    keep_events_ = options.keep_events;
    device::Setup setup;
    setup.model = model;
    setup.config = std::move(options.config);
    setup.plant = options.plant;
    setup.power_on = options.power_on;
    setup.mcemu_version = "test";
    device::Environment env;
    env.storage = &storage_;
    env.unix_ms = [] { return k_fixture_unix_ms; };
    env.now_utc = [] { return std::string("2026-01-15T10:15:02Z"); };
    env.note = [this](const std::string& text) {
      notes.push_back(text);
      if (on_note) on_note(text);
    };
    env.event_tap = [this](const core::Event& e) { tap(e); };
    env.log = [this](device::LogLevel, const std::string& text) {
      if (on_log) on_log(text);
    };
    device_ = std::make_unique<device::Device>(std::move(setup), std::move(env));
  }
  void tap(const core::Event& e) {
    if (keep_events_) events.push_back(e);
    if (on_event) on_event(e);
  }

  MemoryStorage storage_;
  bool keep_events_ = true;
  std::unique_ptr<device::Device> device_;
};

}  // namespace mcemu::testing
