#include "device/fault_gates.hpp"

namespace mcemu::device {

namespace {

Verdict decided(const TransportFaults& faults, Verdict::Action action, std::uint32_t delay_ms = 0) {
  Verdict v;
  v.action = action;
  v.delay = std::chrono::milliseconds(delay_ms);
  v.fault_id = faults.last_taken().id;
  v.kind = faults.last_taken().kind;
  return v;
}

}  // namespace

// Every reply, frame and datagram asks: with no injection active (the usual case) the answer is
// "send" without looking for each kind.
Verdict refgo_reply_verdict(TransportFaults& faults) {
  if (faults.active().empty()) return {};
  if (faults.take_refgo_no_reply()) return decided(faults, Verdict::Action::drop);
  if (const auto ms = faults.refgo_delay_ms()) return decided(faults, Verdict::Action::delay, *ms);
  return {};
}

Verdict node_frame_verdict(TransportFaults& faults, std::uint32_t cob_id) {
  if (faults.active().empty()) return {};
  if (faults.slcan_drop(cob_id)) return decided(faults, Verdict::Action::drop);
  if (const auto ms = faults.slcan_delay_ms()) return decided(faults, Verdict::Action::delay, *ms);
  return {};
}

Verdict udp_datagram_verdict(TransportFaults& faults) {
  if (faults.active().empty()) return {};
  if (faults.take_udp_drop()) return decided(faults, Verdict::Action::drop);
  return {};
}

std::string verdict_text(const Verdict& v, std::string_view what) {
  const std::string by = "(fault " + v.fault_id + " " + std::string(to_string(v.kind)) + ")";
  switch (v.action) {
    case Verdict::Action::send: break;
    case Verdict::Action::drop: return std::string(what) + " not sent " + by;
    case Verdict::Action::delay:
      return std::string(what) + " held back " + std::to_string(v.delay.count()) + " ms " + by;
  }
  return std::string(what) + " sent";
}

}  // namespace mcemu::device
