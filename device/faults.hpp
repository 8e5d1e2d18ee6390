// Fault injection over HTTP (web.md §9, slcan-canopen.md §11.3): POST /api/v1/faults creates an
// injection, GET lists the active ones, DELETE /api/v1/faults/{id} removes one, DELETE
// /api/v1/faults removes all.
//
// PURE and single-threaded. The drive kinds act on the drive core through its injection interface
// (drive-core.md §11.9); the transport kinds become entries of TransportFaults, which the network
// adapters consult; script.kill calls the script-kill hook (503 without a script engine, 409 while no
// script runs).
//
// Every kind takes the optional "count" and "durationMs" (drive time). durationMs removes the
// injection when that much drive time has passed (on_step()). count removes it after n
// occurrences: for the transport kinds an occurrence is one reply, datagram, frame, transfer,
// request, heartbeat or line it affected; for the drive kinds it is one fault raised while the
// injection is active (a 1002h error bit rising; for drive.inject: its own cause's bit). The
// one-shot kinds (drive.emcy, refgo.disconnect, slcan.disconnect, slcan.rawTx) act once.
// Every injection and removal is reported through the journal hook (trace channel `api`, UDP note).
//
// Contract: the dictionary and the core outlive this object; on_step() runs after every drive step.
// When drive time restarts (a power on sets it to 0), each duration keeps the time it had left.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/liveness.hpp"
#include "device/refusal.hpp"
#include "device/transport_faults.hpp"

namespace mcemu::core {
class DriveCore;
}
namespace mcemu::od {
class ObjectDictionary;
}

namespace mcemu::device {

class FaultInjections {
 public:
  // trace_text goes to the trace (channel api), note_text to the UDP emulator notes.
  using Journal = std::function<void(const std::string& trace_text, const std::string& note_text)>;

  FaultInjections(od::ObjectDictionary& od, core::DriveCore& core);
  ~FaultInjections();
  FaultInjections(const FaultInjections&) = delete;
  FaultInjections& operator=(const FaultInjections&) = delete;

  void set_journal(Journal j) { journal_ = std::move(j); }
  // script.kill: `running` tells whether an engine process exists (else 409), `kill` kills it;
  // empty = no engine (503).
  void set_script_kill(std::function<bool()> running, std::function<void()> kill) {
    script_running_ = std::move(running);
    kill_script_ = std::move(kill);
  }

  // POST /api/v1/faults: the listed injection (with its "id") or why it was refused.
  Outcome<nlohmann::json> create(const std::string& body);
  // {"faults": [...]}: the active injections with "remaining" and "expiresAtMs" where they apply.
  nlohmann::json list() const;
  // Removes one injection (Refusal::Kind::not_found if there is none with that id), or all.
  std::optional<Refusal> remove(const std::string& id);
  void remove_all();
  // Removes the injections whose duration is over or whose count is used up; after every step.
  void on_step();
  // The earliest drive time at which on_step() removes an injection (none without a duration; now
  // while an injection has used up its count).
  std::optional<std::uint64_t> next_expiry() const;
  std::size_t active() const { return active_.size(); }
  // The fault bits in the 1002h layout (core::DriveCore::fault_bits()) after the drive changed:
  // how drive kinds count occurrences on a drive without 1002h (FAULHABER); with 1002h the
  // injections watch the entry themselves.
  void observe_fault_bits(std::uint32_t bits) {
    if (bits != last_1002_) on_fault_bits(bits);
  }
  // Which kinds this drive has (a FAULHABER MC has no RefGo, SLCAN, UDP or scripts): a kind it
  // lacks is refused as unavailable instead of being listed and doing nothing.
  void set_kind_filter(std::function<bool(std::string_view kind)> available) { available_ = std::move(available); }

  TransportFaults& transport() { return transport_; }

 private:
  struct Injection {
    std::string id;
    std::string kind;
    nlohmann::json description;              // the kind and its fields, as listed
    std::optional<std::uint64_t> expires;    // drive time in ms
    std::optional<std::uint64_t> remaining;  // drive kinds: faults still to count
    std::optional<int> cause_bit;            // drive.inject: the 1002h bit of its cause
    bool transport = false;
    bool used_up = false;        // count reached: removed at the next on_step()
    std::function<void()> undo;  // called on removal (may be empty)
  };
  struct Parsed;
  using Parser = std::optional<Refusal> (FaultInjections::*)(const nlohmann::json& body, Parsed& out);
  struct KindRow {
    const char* name;
    std::vector<const char*> fields;  // besides kind, count, durationMs
    Parser parse;
  };
  static const std::vector<KindRow>& kinds();

  std::optional<Refusal> parse_inject(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_emcy(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_supply(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_ambient(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_load(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_obstacle(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_transport(const nlohmann::json& b, Parsed& out);
  std::optional<Refusal> parse_script_kill(const nlohmann::json& b, Parsed& out);

  void on_fault_bits(std::uint32_t value);
  void erase(const std::string& id, std::string_view reason, bool undo);
  void report(const std::string& trace_text, const std::string& note_text);

  od::ObjectDictionary& od_;
  core::DriveCore& core_;
  TransportFaults transport_;
  std::vector<Injection> active_;
  std::uint64_t next_id_ = 1;
  std::uint32_t last_1002_ = 0;
  std::uint64_t last_time_ms_ = 0;  // drive time of the previous on_step()
  Journal journal_;
  std::function<bool()> script_running_;
  std::function<void()> kill_script_;
  std::function<bool(std::string_view)> available_;
  base::LivenessToken alive_;  // the OD change listener checks this is still alive
};

}  // namespace mcemu::device
