// The transport-side fault injections of web.md §9 and slcan-canopen.md §11.3 as decisions the
// network adapters ask for: "drop this reply?", "delay this frame by how long?", "abort this SDO
// transfer at this phase?". Created and removed through FaultInjections (POST/DELETE
// /api/v1/faults), which also expires them by drive time.
//
// PURE and single-threaded (event loop). Every query that applies an injection counts one
// occurrence: an injection with a count removes itself after its last occurrence and reports that
// through the removed-listener. Queries that find nothing change nothing. When several injections
// of one kind match, the oldest one is used.
//
// Who asks (the lead wires it):
//   RefGo session/adapter, per reply:  take_refgo_no_reply(), then refgo_delay_ms()
//   UDP debug service, per datagram:   take_udp_drop()
//   HTTP router (itself), per page:    take_http_error(path)
//   SLCAN/CANopen bus, per node frame: slcan_drop(cob_id), then slcan_delay_ms()
//   SDO server, per request/phase:     take_sdo_no_reply(index), slcan_sdo_abort(index, sub, phase)
//   heartbeat producer, per heartbeat: take_heartbeat_stop()
//   SLCAN session, per command line:   take_slcan_bel()
//   the server, when notified:         drain_actions() (refgo.disconnect, slcan.disconnect, slcan.rawTx)
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trace/trace.hpp"

namespace mcemu::device {

enum class TransportKind : std::uint8_t {
  refgo_no_reply,
  refgo_delay,
  refgo_disconnect,
  udp_drop,
  http_error,
  slcan_drop_tx,
  slcan_delay_tx,
  slcan_sdo_abort,
  slcan_sdo_no_reply,
  slcan_heartbeat_stop,
  slcan_raw_tx,
  slcan_bel,
  slcan_disconnect
};

// The phase of an SDO transfer at which slcan.sdoAbort answers with its abort frame.
enum class SdoPhase : std::uint8_t { initiate, segment, end };

struct TransportFault {
  std::string id;
  TransportKind kind = TransportKind::refgo_no_reply;
  std::optional<std::uint64_t> remaining;  // occurrences left; nullopt = until removed or expired
  std::uint32_t ms = 0;                    // refgo.delay, slcan.delayTx (wall time)
  int status = 0;                          // http.error
  std::string path;                        // http.error: path prefix ("" = every page)
  std::optional<std::uint32_t> cob_id;     // slcan.dropTx: only this identifier
  std::optional<std::uint16_t> index;      // slcan.sdoAbort (always), slcan.sdoNoReply (optional)
  std::uint8_t sub = 0;                    // slcan.sdoAbort
  std::uint32_t abort_code = 0;            // slcan.sdoAbort
  SdoPhase phase = SdoPhase::initiate;     // slcan.sdoAbort
  std::string text;                        // slcan.rawTx
};

// A one-shot action the server performs once (refgo.disconnect, slcan.disconnect, slcan.rawTx).
struct TransportAction {
  TransportKind kind = TransportKind::refgo_disconnect;
  std::string text;  // slcan.rawTx: the bytes to write to every SLCAN session
};

struct SdoAbortPlan {
  std::uint32_t code = 0;  // the abort code to send (the OD is not touched)
};

// True for the kinds that act once when created (their action is queued for drain_actions()).
bool is_one_shot(TransportKind k);
// The kind's name in the API ("refgo.noReply") and the trace channel its effects belong to.
std::string_view to_string(TransportKind k);
trace::Channel trace_channel(TransportKind k);
// The trace text of one application: "fault f3 refgo.noReply applied".
std::string applied_text(const TransportFault& f);

class TransportFaults {
 public:
  // Called when an injection removes itself: reason "count" (last occurrence) or "done" (a
  // one-shot action was drained).
  using RemovedListener = std::function<void(const std::string& id, std::string_view reason)>;

  void set_removed_listener(RemovedListener l) { removed_ = std::move(l); }
  // Called when a one-shot action is queued, so that the server can drain it soon.
  void set_action_listener(std::function<void()> l) { action_ = std::move(l); }
  // Called for every occurrence an injection affects (each take that matched, each drained action),
  // before a count that is used up removes it.
  using AppliedListener = std::function<void(const TransportFault& f)>;
  void set_applied_listener(AppliedListener l) { applied_ = std::move(l); }

  void add(TransportFault f);
  // Removes an injection without calling the removed-listener (the caller reports it).
  bool remove(const std::string& id);
  void clear();
  const std::vector<TransportFault>& active() const { return active_; }

  bool take_refgo_no_reply();
  std::optional<std::uint32_t> refgo_delay_ms();
  bool take_udp_drop();
  std::optional<int> take_http_error(std::string_view path);
  bool slcan_drop(std::uint32_t cob_id);
  std::optional<std::uint32_t> slcan_delay_ms();
  std::optional<SdoAbortPlan> slcan_sdo_abort(std::uint16_t index, std::uint8_t sub, SdoPhase phase);
  bool take_sdo_no_reply(std::uint16_t index);
  bool take_heartbeat_stop();
  bool take_slcan_bel();

  // The injection the latest successful query used (a copy: it may have been removed since).
  const TransportFault& last_taken() const { return taken_; }

  bool has_actions() const { return !actions_.empty(); }
  // The queued one-shot actions, oldest first; their injections are then removed ("done").
  std::vector<TransportAction> drain_actions();

 private:
  // The first active injection of `kind` that `match` accepts, counted as one occurrence.
  template <typename Match>
  const TransportFault* take(TransportKind kind, Match match);

  std::vector<TransportFault> active_;
  std::vector<std::pair<std::string, TransportAction>> actions_;
  TransportFault taken_;  // copy of the injection a take() used (it may have been removed)
  RemovedListener removed_;
  std::function<void()> action_;
  AppliedListener applied_;
};

}  // namespace mcemu::device
