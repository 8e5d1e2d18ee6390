// Fault injection over HTTP (web.md §9): POST /api/v1/faults creates an injection, GET lists the
// active ones, DELETE /api/v1/faults/{id} removes one, DELETE /api/v1/faults removes all. PURE: it
// acts on the drive core through its injection interface (drive-core.md §11.9) and expires
// injections by drive time (on_step()).
//
// Kinds available today: drive.inject, drive.emcy, drive.supply, drive.ambient, drive.load,
// drive.obstacle, with the optional "durationMs" (drive time). The protocol-side kinds (refgo.*,
// udp.drop, http.error, script.kill, slcan.*) and "count" belong to the web milestone and are
// refused with 400 naming the kind.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "web/api/router.hpp"

namespace mcemu::core {
class DriveCore;
}

namespace mcemu::web::api {

class FaultInjections {
 public:
  explicit FaultInjections(core::DriveCore& core) : core_(core) {}
  FaultInjections(const FaultInjections&) = delete;
  FaultInjections& operator=(const FaultInjections&) = delete;

  Response create(const std::string& body);
  Response list() const;
  Response remove(const std::string& id);
  Response remove_all();
  // Removes the injections whose drive-time duration is over; call after every drive step.
  void on_step();
  std::size_t active() const { return active_.size(); }

 private:
  struct Injection {
    std::string id;
    nlohmann::json description;            // the kind and its fields, as listed
    std::optional<std::uint64_t> expires;  // drive time in ms
    std::function<void()> undo;            // called on removal (may be empty)
  };
  void undo(Injection& i);

  core::DriveCore& core_;
  std::vector<Injection> active_;
  std::uint64_t next_id_ = 1;
};

}  // namespace mcemu::web::api
