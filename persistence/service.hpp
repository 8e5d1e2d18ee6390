// Store Permanently / Factory Reset / motor-parameter store (persistence.md §3, §4, §12, §13).
//
// Registers the write hooks of 1010h.01–.03, 1011h.01–.03 and 3010h.01 on the dictionary. A hook
// checks the signature (0x08000020) and, for a restore, the drive state (0x08000022), takes the
// snapshot on the event-loop thread, hands the file write to `Storage` and answers `pending`; the
// OD write completes (done callback) when the file is durable or the write failed (0x06060000).
// Requests run strictly in arrival order, each writing the snapshot of its own arrival. A restore
// changes RAM only after its file is durable, so a failed restore changes nothing.
// A completion that arrives after the service is gone (the drive was shut down and destroyed while a
// file was being written) is dropped: the dictionary it would update and the caller it would answer
// are gone with it.
// Threading: every call and callback on the event-loop thread. PURE: the file write is the Storage's
// (persistence/worker_storage.hpp in the server), the log lines go through the hooks.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "base/liveness.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/objects.hpp"
#include "persistence/state_document.hpp"

namespace mcemu::persistence {

inline constexpr std::int64_t k_save = od::k_save_signature;  // "save"
inline constexpr std::int64_t k_load = od::k_load_signature;  // "load"

// Writes the state file; completion is delivered on the event-loop thread in request order (also
// after the Service that asked is gone: it checks).
class Storage {
 public:
  virtual ~Storage() = default;
  using Completion = std::function<void(std::optional<std::string> error)>;
  virtual void write_state(std::string contents, Completion done) = 0;
};

struct ServiceHooks {
  std::function<bool()> operation_enabled;            // a restore is refused while true
  std::function<std::int64_t()> home_offset_inc;      // stored for absolute-encoder models
  std::function<void()> after_restore;                // RAM image changed by a bulk load (core, node, iofunc)
  std::function<void()> reset_script;                 // stop the script, load the placeholder
  std::function<std::string()> now_utc;               // "2026-01-15T10:15:02Z" for written_utc
  std::function<void(const std::string&)> log_info;   // "factory reset done: …"
  std::function<void(const std::string&)> log_error;  // "store failed: …"
};

class Service {
 public:
  // `factory` makes the factory image (XDD → preset → --config) the first time it is needed (a
  // restore, a motor store, a factory value asked for): most drives never need it, and a fleet
  // would hold one copy per drive. It must give the same image whenever it is called. `on_file` is
  // what the state file holds (nullopt if none was loaded).
  Service(od::ObjectDictionary& od, std::string model, std::string mcemu_version, std::function<Image()> factory,
          std::optional<Image> on_file, Storage& storage, ServiceHooks hooks);

  const Image& factory() const;
  // What the state file holds now (nullopt if nothing was stored): NMT reset node / reset
  // communication rebuild RAM from factory() + on_file() (persistence.md §5, §7).
  const std::optional<Image>& on_file() const { return durable_; }
  // The uploaded script of the program group (null = placeholder); scripting sets it.
  const nlohmann::json& script() const { return script_; }
  void set_script(nlohmann::json script) { script_ = std::move(script); }
  std::size_t in_flight() const { return in_flight_; }

 private:
  od::AbortCode store_all(od::WriteRequest& req);
  od::AbortCode restore_all(od::WriteRequest& req);
  od::AbortCode store_motor(od::WriteRequest& req);
  Image with_counter(Image img);
  void submit(Image img, od::Done done, std::function<void(bool ok)> after);
  void count_event(bool ok);

  od::ObjectDictionary& od_;
  std::string model_;
  std::string version_;
  std::function<Image()> make_factory_;
  mutable std::optional<Image> factory_;  // made by make_factory_ on first use
  std::optional<Image> durable_;          // what the file holds now
  std::optional<Image> expected_;         // what it will hold when the queued writes are done
  Storage& storage_;
  ServiceHooks hooks_;
  nlohmann::json script_;
  std::int64_t next_counter_ = 0;
  std::size_t in_flight_ = 0;
  base::LivenessToken alive_;  // the storage's completions check it
};

}  // namespace mcemu::persistence
