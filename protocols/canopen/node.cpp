#include "protocols/canopen/node.hpp"

#include "protocols/canopen/comm_reload.hpp"
#include "protocols/canopen/od_access.hpp"

namespace mcemu::canopen {

Node::Node(od::ObjectDictionary& od, CanopenConfig config, Hooks hooks)
    : od_(od),
      config_(config),
      hooks_(std::move(hooks)),
      sdo_(od, config_,
           [this] {
             if (hooks_.after_od_write) hooks_.after_od_write();
           }),
      tpdo_(od),
      rpdo_(od, RpdoSet::Hooks{[this](std::uint16_t code, std::uint8_t reg) { emit_emcy(code, reg); },
                               [this] {
                                 if (hooks_.after_od_write) hooks_.after_od_write();
                               },
                               [this](const std::string& text) {
                                 if (hooks_.diagnostic) hooks_.diagnostic(text);
                               }}),
      heartbeat_(od),
      guarding_(od) {
  sdo_.set_wake([this] {
    if (!in_call_ && hooks_.wake) hooks_.wake();
  });
  if (od_.find(0x1017, 0)) {
    od_.on_write(0x1017, 0, [this](od::WriteRequest& req) {
      const auto period = std::get<std::int64_t>(req.value);
      heartbeat_.written(period, now_);
      if (period != 0) guarding_.cancel_life_guarding();
      return od::AbortCode::none;
    });
  }
}

void Node::set_faults(Faults faults) {
  sdo_.set_faults(std::move(faults.sdo));
  heartbeat_stop_ = std::move(faults.heartbeat_stop);
}

Node::~Node() {
  if (od_.find(0x1017, 0)) od_.on_write(0x1017, 0, {});
}

std::uint32_t Node::cob(std::uint16_t index, std::uint8_t sub, std::uint32_t predefined_base) const {
  const auto v = stored_number(od_, index, sub);
  return v ? static_cast<std::uint32_t>(*v) : predefined_base + node_id_;
}

void Node::apply_node_id_from_od() {
  const auto id = stored_number(od_, 0x3404, 3);
  const auto next = static_cast<std::uint8_t>(id && *id >= 1 && *id <= 127 ? *id : node_id_);
  apply_node_id(od_, node_id_, next);
  node_id_ = next;
}

void Node::power_on(Millis now) {
  begin(now);
  out_ = Outbox{};
  sdo_.reset();
  node_id_ = k_factory_node_id;  // the factory image's COB-IDs are computed for node 50
  apply_node_id_from_od();
  guarding_.reset();
  rpdo_.reset();
  tpdo_.leave_operational();
  state_ = NmtState::initialising;
  bootup_at_ = now + config_.bootup_delay_reset_communication;
  in_call_ = false;
}

void Node::begin(Millis now) {
  now_ = now;
  in_call_ = true;
}

std::vector<can::Frame> Node::finish() {
  in_call_ = false;
  return out_.flatten();
}

std::vector<can::Frame> Node::on_frame(const can::Frame& f, Millis now) {
  begin(now);
  if (f.extended) return finish();
  if (state_ == NmtState::initialising) {
    // slcan-canopen.md §4.4: frames are ignored until the boot-up, except a reset node or reset
    // communication of this node, which is executed (the boot-up delay starts again).
    if (f.id == 0 && !f.rtr && f.dlc == 2 && (f.data[0] == 0x81 || f.data[0] == 0x82)) on_nmt(f);
    return finish();
  }
  const std::uint32_t sync_id = cob(0x1005, 0, 0x80) & 0x7FF;
  const std::uint32_t sdo_id = cob(0x1200, 1, 0x600) & 0x7FF;
  if (f.id == 0 && !f.rtr) {
    on_nmt(f);
  } else if (f.id == sync_id && !f.rtr) {
    if (f.dlc <= 1) on_sync();
  } else if (f.id == sdo_id && !f.rtr) {
    on_sdo(f);
  } else if (f.id == 0x700u + node_id_ && f.rtr) {
    on_guarding_rtr();
  } else if (state_ == NmtState::operational) {
    if (f.rtr) {
      tpdo_.on_rtr(f.id, now_, out_);
    } else {
      rpdo_.on_frame(f);
    }
  }
  if (state_ == NmtState::operational) tpdo_.check(now_, out_);
  return finish();
}

std::vector<can::Frame> Node::advance(Millis now) {
  begin(now);
  if (state_ == NmtState::initialising) {
    if (bootup_at_ && now_ >= *bootup_at_) {
      bootup_at_.reset();
      const std::uint8_t zero = 0;
      out_.error_control.push_back(make_frame(0x700u + node_id_, &zero, 1));
      state_ = NmtState::pre_operational;
      heartbeat_.restart(now_);
    }
    return finish();
  }
  if (state_ != NmtState::stopped) {
    std::vector<Payload> responses;
    sdo_.advance(now_, responses);
    if (!responses.empty()) {
      const std::uint32_t tx = cob(0x1200, 2, 0x580);
      for (const auto& p : responses) out_.sdo.push_back(make_frame(tx, p.data(), p.size()));
    }
  }
  if (guarding_.advance(now_, heartbeat_.enabled())) life_guarding_expired();
  if (state_ == NmtState::operational) tpdo_.check(now_, out_);
  heartbeat_.advance(now_, state_, node_id_, out_);
  if (!out_.heartbeat.empty() && heartbeat_stop_ && heartbeat_stop_()) out_.heartbeat.clear();
  return finish();
}

std::optional<Millis> Node::next_deadline() const {
  if (!out_.empty() || sdo_.has_completions()) return now_;
  if (state_ == NmtState::initialising) return bootup_at_;
  std::optional<Millis> best;
  const auto consider = [&](std::optional<Millis> t) {
    if (t && (!best || *t < *best)) best = t;
  };
  if (state_ != NmtState::stopped) consider(sdo_.next_deadline());
  consider(guarding_.next_deadline());
  if (state_ == NmtState::operational) consider(tpdo_.next_deadline());
  consider(heartbeat_.next_deadline());
  return best;
}

void Node::emit_emcy(std::uint16_t code, std::uint8_t error_register, const std::array<std::uint8_t, 5>& data) {
  if (state_ != NmtState::pre_operational && state_ != NmtState::operational) return;
  const auto cob_id = stored_number(od_, 0x1014, 0);
  if (!cob_id || (*cob_id & k_cob_invalid) != 0) return;
  const std::uint8_t bytes[8] = {static_cast<std::uint8_t>(code & 0xFF),
                                 static_cast<std::uint8_t>(code >> 8),
                                 error_register,
                                 data[0],
                                 data[1],
                                 data[2],
                                 data[3],
                                 data[4]};
  out_.emcy.push_back(make_frame(static_cast<std::uint32_t>(*cob_id), bytes, 8));
  if (!in_call_ && hooks_.wake) hooks_.wake();
}

void Node::reload() { heartbeat_.resync(now_); }

void Node::on_nmt(const can::Frame& f) {
  if (f.dlc != 2 || (f.data[1] != 0 && f.data[1] != node_id_)) return;
  switch (f.data[0]) {
    case 0x01: set_state(NmtState::operational); return;
    case 0x02: set_state(NmtState::stopped); return;
    case 0x80: set_state(NmtState::pre_operational); return;
    case 0x81: reset(true); return;
    case 0x82: reset(false); return;
    default: return;
  }
}

void Node::set_state(NmtState next) {
  if (next == state_) return;
  const NmtState prev = state_;
  state_ = next;
  if (prev == NmtState::operational) {
    tpdo_.leave_operational();
    rpdo_.leave_operational();
  }
  if (next == NmtState::stopped) sdo_.reset();
  if (next == NmtState::operational) tpdo_.enter_operational(now_, out_);
}

void Node::reset(bool whole_node) {
  sdo_.reset();  // a running transfer ends silently
  if (whole_node) {
    if (hooks_.reset_node) {
      hooks_.reset_node();
    } else {
      reload_communication_objects(od_);
    }
  } else if (hooks_.reset_communication) {
    hooks_.reset_communication();
  } else {
    reload_communication_objects(od_);
  }
  apply_node_id_from_od();
  guarding_.reset();
  rpdo_.reset();
  tpdo_.leave_operational();
  state_ = NmtState::initialising;
  bootup_at_ = now_ + (whole_node ? config_.bootup_delay_reset_node : config_.bootup_delay_reset_communication);
}

void Node::on_sdo(const can::Frame& f) {
  if (f.dlc != 8) return;
  if (state_ != NmtState::pre_operational && state_ != NmtState::operational) return;
  Payload req{};
  std::copy(f.data.begin(), f.data.end(), req.begin());
  std::vector<Payload> responses;
  sdo_.on_request(req, now_, responses);
  const std::uint32_t tx = cob(0x1200, 2, 0x580);
  for (const auto& p : responses) out_.sdo.push_back(make_frame(tx, p.data(), p.size()));
}

void Node::on_sync() {
  if (state_ != NmtState::operational) return;
  rpdo_.on_sync();
  tpdo_.on_sync(now_, out_);
}

void Node::on_guarding_rtr() {
  const auto reply = guarding_.on_rtr(state_, heartbeat_.enabled(), now_);
  if (reply) out_.error_control.push_back(make_frame(0x700u + node_id_, &*reply, 1));
}

void Node::life_guarding_expired() {
  if (hooks_.diagnostic) hooks_.diagnostic("life guarding: life time expired");
  if (hooks_.connection_lost) hooks_.connection_lost();
  switch (stored_number_or(od_, 0x1029, 1, 0)) {
    case 0:
      if (state_ == NmtState::operational) set_state(NmtState::pre_operational);
      return;
    case 2: set_state(NmtState::stopped); return;
    default: return;
  }
}

}  // namespace mcemu::canopen
