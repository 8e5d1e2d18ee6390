#include "device/transport_faults.hpp"

#include <algorithm>

namespace mcemu::device {

bool is_one_shot(TransportKind k) {
  return k == TransportKind::refgo_disconnect || k == TransportKind::slcan_disconnect ||
         k == TransportKind::slcan_raw_tx;
}

std::string_view to_string(TransportKind k) {
  switch (k) {
    case TransportKind::refgo_no_reply: return "refgo.noReply";
    case TransportKind::refgo_delay: return "refgo.delay";
    case TransportKind::refgo_disconnect: return "refgo.disconnect";
    case TransportKind::udp_drop: return "udp.drop";
    case TransportKind::http_error: return "http.error";
    case TransportKind::slcan_drop_tx: return "slcan.dropTx";
    case TransportKind::slcan_delay_tx: return "slcan.delayTx";
    case TransportKind::slcan_sdo_abort: return "slcan.sdoAbort";
    case TransportKind::slcan_sdo_no_reply: return "slcan.sdoNoReply";
    case TransportKind::slcan_heartbeat_stop: return "slcan.heartbeatStop";
    case TransportKind::slcan_raw_tx: return "slcan.rawTx";
    case TransportKind::slcan_bel: return "slcan.bel";
    case TransportKind::slcan_disconnect: return "slcan.disconnect";
  }
  return "?";
}

trace::Channel trace_channel(TransportKind k) {
  switch (k) {
    case TransportKind::refgo_no_reply:
    case TransportKind::refgo_delay:
    case TransportKind::refgo_disconnect: return trace::Channel::refgo;
    case TransportKind::udp_drop: return trace::Channel::udp;
    case TransportKind::http_error: return trace::Channel::http;
    default: return trace::Channel::slcan;
  }
}

std::string applied_text(const TransportFault& f) {
  return "fault " + f.id + " " + std::string(to_string(f.kind)) + " applied";
}

void TransportFaults::add(TransportFault f) {
  if (is_one_shot(f.kind)) {
    actions_.push_back({f.id, TransportAction{f.kind, f.text}});
    active_.push_back(std::move(f));
    if (action_) action_();
    return;
  }
  active_.push_back(std::move(f));
}

bool TransportFaults::remove(const std::string& id) {
  const auto it = std::find_if(active_.begin(), active_.end(), [&](const TransportFault& f) { return f.id == id; });
  if (it == active_.end()) return false;
  active_.erase(it);
  std::erase_if(actions_, [&](const auto& a) { return a.first == id; });
  return true;
}

void TransportFaults::clear() {
  active_.clear();
  actions_.clear();
}

template <typename Match>
const TransportFault* TransportFaults::take(TransportKind kind, Match match) {
  const auto it =
      std::find_if(active_.begin(), active_.end(), [&](const TransportFault& f) { return f.kind == kind && match(f); });
  if (it == active_.end()) return nullptr;
  taken_ = *it;
  if (applied_) applied_(taken_);
  if (it->remaining) {
    --*it->remaining;
    if (*it->remaining == 0) {
      const std::string id = it->id;
      active_.erase(it);
      if (removed_) removed_(id, "count");
    }
  }
  return &taken_;
}

namespace {
constexpr auto any = [](const TransportFault&) { return true; };
}

bool TransportFaults::take_refgo_no_reply() { return take(TransportKind::refgo_no_reply, any) != nullptr; }

std::optional<std::uint32_t> TransportFaults::refgo_delay_ms() {
  const auto* f = take(TransportKind::refgo_delay, any);
  if (!f) return std::nullopt;
  return f->ms;
}

bool TransportFaults::take_udp_drop() { return take(TransportKind::udp_drop, any) != nullptr; }

std::optional<int> TransportFaults::take_http_error(std::string_view path) {
  const auto* f =
      take(TransportKind::http_error, [&](const TransportFault& t) { return path.substr(0, t.path.size()) == t.path; });
  if (!f) return std::nullopt;
  return f->status;
}

bool TransportFaults::slcan_drop(std::uint32_t cob_id) {
  return take(TransportKind::slcan_drop_tx,
              [&](const TransportFault& t) { return !t.cob_id || *t.cob_id == cob_id; }) != nullptr;
}

std::optional<std::uint32_t> TransportFaults::slcan_delay_ms() {
  const auto* f = take(TransportKind::slcan_delay_tx, any);
  if (!f) return std::nullopt;
  return f->ms;
}

std::optional<SdoAbortPlan> TransportFaults::slcan_sdo_abort(std::uint16_t index, std::uint8_t sub, SdoPhase phase) {
  const auto* f = take(TransportKind::slcan_sdo_abort,
                       [&](const TransportFault& t) { return t.index == index && t.sub == sub && t.phase == phase; });
  if (!f) return std::nullopt;
  return SdoAbortPlan{f->abort_code};
}

bool TransportFaults::take_sdo_no_reply(std::uint16_t index) {
  return take(TransportKind::slcan_sdo_no_reply,
              [&](const TransportFault& t) { return !t.index || *t.index == index; }) != nullptr;
}

bool TransportFaults::take_heartbeat_stop() { return take(TransportKind::slcan_heartbeat_stop, any) != nullptr; }

bool TransportFaults::take_slcan_bel() { return take(TransportKind::slcan_bel, any) != nullptr; }

std::vector<TransportAction> TransportFaults::drain_actions() {
  std::vector<TransportAction> out;
  auto queued = std::move(actions_);
  actions_.clear();
  for (auto& entry : queued) {
    const auto id = entry.first;  // not a structured binding: clang 14 cannot capture those
    out.push_back(std::move(entry.second));
    const auto it = std::find_if(active_.begin(), active_.end(), [&](const TransportFault& f) { return f.id == id; });
    if (it != active_.end()) {
      if (applied_) applied_(*it);
      active_.erase(it);
      if (removed_) removed_(id, "done");
    }
  }
  return out;
}

}  // namespace mcemu::device
