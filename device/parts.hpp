// The parts a drive bundle steps after its drive core (sim/drive_steps.hpp), each saying how many
// steps it can be left alone: fault-injection durations, the scope sampler, the RefGo programs and
// the CANopen bus. The order of the parts is the bundle's (device/device.hpp).
#pragma once

#include <cstdint>

#include "device/canopen_bus.hpp"
#include "device/faults.hpp"
#include "device/lint_hub.hpp"
#include "device/scope.hpp"
#include "drive/drive_core.hpp"
#include "protocols/faulhaber/port.hpp"
#include "protocols/refgo/interpreter.hpp"
#include "scripting/basic/programs.hpp"
#include "sim/drive_steps.hpp"

namespace mcemu::device {

// Removes fault injections whose drive-time duration is over or whose count is used up.
class FaultsPart final : public sim::Part {
 public:
  FaultsPart(FaultInjections& faults, const core::DriveCore& core) : faults_(faults), core_(core) {}
  void step() override { faults_.on_step(); }
  std::uint64_t quiet_steps() const override;
  void prefetch() const override { __builtin_prefetch(&faults_); }

 private:
  FaultInjections& faults_;
  const core::DriveCore& core_;
};

// The scope of web.md §5.3: a sample every 5 ms of drive time. In a quiet stretch the sampled
// objects are constant, so a skip adds the samples it passed (the last 60 s of them) at once.
class ScopePart final : public sim::Part {
 public:
  ScopePart(Scope& scope, const core::DriveCore& core, const od::ObjectDictionary& od)
      : scope_(scope), core_(core), od_(od) {}
  void step() override { scope_.on_step(core_.time_ms(), od_); }
  std::uint64_t quiet_steps() const override { return sim::k_forever; }
  void skip(std::uint64_t n) override;
  void prefetch() const override { __builtin_prefetch(&scope_); }

 private:
  Scope& scope_;
  const core::DriveCore& core_;
  const od::ObjectDictionary& od_;
};

// The RefGo interpreter's programs: the jog timer and Back & Forth (refgo.md §7.6, §7.7).
class RefgoPart final : public sim::Part {
 public:
  RefgoPart(refgo::Interpreter& refgo, const core::DriveCore& core) : refgo_(refgo), core_(core) {}
  void step() override { refgo_.on_step(); }
  std::uint64_t quiet_steps() const override;
  void prefetch() const override { __builtin_prefetch(&refgo_); }

 private:
  refgo::Interpreter& refgo_;
  const core::DriveCore& core_;
};

// The CANopen bus: stepped after the drive and the event hand-off, quiet until the node's next
// deadline (boot-up, heartbeat, TPDO event/inhibit timers, SDO timeout, life guarding, pending
// output). A skip advances the bus time and runs the node once at the end, which does nothing when
// no deadline fell inside (the node's advance() at a time before every deadline is a no-op).
class CanopenPart final : public sim::Part {
 public:
  explicit CanopenPart(CanopenBus& bus) : bus_(bus) {}
  void step() override { bus_.step(); }
  std::uint64_t quiet_steps() const override;
  void skip(std::uint64_t n) override;
  void prefetch() const override { __builtin_prefetch(&bus_); }

 private:
  CanopenBus& bus_;
};

// The FAULHABER port: responses held back by faulhaber.response_delay_ms or behind a Store come out
// in drive time; quiet until the port's next deadline.
class FaulhaberPart final : public sim::Part {
 public:
  FaulhaberPart(faulhaber::Port& port, const core::DriveCore& core) : port_(port), core_(core) {}
  void step() override;
  std::uint64_t quiet_steps() const override;
  void skip(std::uint64_t n) override;

 private:
  faulhaber::Port& port_;
  const core::DriveCore& core_;
};

// MC BASIC (faulhaber.md §9.9): up to N statements per 1 ms step after the drive core; quiet while
// no program runs or the running one only waits on values that do not change.
class BasicPart final : public sim::Part {
 public:
  // `lint`: told after each step how long the running program has gone without waiting.
  BasicPart(basic::Programs& programs, const core::DriveCore& core, LintHub* lint = nullptr)
      : programs_(programs), core_(core), lint_(lint && lint->active() ? lint : nullptr) {}
  void step() override {
    programs_.step(core_.time_ms());
    if (lint_ && programs_.running() != 0) {
      lint_->script_loop(lint::ScriptKind::basic, programs_.interpreter().statements_since_wait());
    }
  }
  std::uint64_t quiet_steps() const override { return programs_.quiet_steps(); }
  void skip(std::uint64_t n) override { programs_.skip(n); }

 private:
  basic::Programs& programs_;
  const core::DriveCore& core_;
  LintHub* lint_;
};

}  // namespace mcemu::device
