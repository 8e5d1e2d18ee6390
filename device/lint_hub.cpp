#include "device/lint_hub.hpp"

#include <utility>

#include "lint/canopen_view.hpp"
#include "protocols/faulhaber/frame.hpp"

namespace mcemu::device {

// One connection of a line protocol as the lint sees it: a read is a chunk in the connection's
// scope, the end is ConnectionClosed. Everything else is the inner session's.
class LintHub::Session final : public line::StreamSession {
 public:
  Session(LintHub& hub, std::unique_ptr<line::StreamSession> inner, lint::Conn conn)
      : hub_(&hub), alive_(hub.alive_.watch()), inner_(std::move(inner)), conn_(conn) {
    inner_->set_wake([this] { wake(); });
  }
  ~Session() override {
    if (alive_) hub_->closed(conn_);
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void receive(std::string_view bytes) override {
    if (!alive_) return inner_->receive(bytes);
    const auto scope = hub_->serve(conn_, ++hub_->next_chunk_);
    inner_->receive(bytes);
  }
  std::string take_output() override { return inner_->take_output(); }
  void peer_closed() override { inner_->peer_closed(); }
  bool finished() const override { return inner_->finished(); }
  bool paused() const override { return inner_->paused(); }
  void closing(std::string_view reason) override { inner_->closing(reason); }

 private:
  LintHub* hub_;
  base::Liveness alive_;
  std::unique_ptr<line::StreamSession> inner_;
  lint::Conn conn_;
};

LintHub::LintHub(lint::Config config, od::ObjectDictionary& od, const core::DriveCore& core, lint::Engine::Sink sink)
    : od_(od),
      core_(core),
      engine_(std::move(config), std::move(sink)),
      statusword_(od.find(0x6041, 0)),
      controlword_(od.find(0x6040, 0)),
      mode_(od.find(0x6060, 0)),
      mode_display_(od.find(0x6061, 0)),
      target_velocity_(od.find(0x60FF, 0)) {}

std::unique_ptr<line::StreamSession> LintHub::wrap(std::unique_ptr<line::StreamSession> inner, lint::Conn conn) {
  if (!active()) return inner;
  return std::make_unique<Session>(*this, std::move(inner), conn);
}

faulhaber::Port::Trace LintHub::faulhaber_trace(lint::Conn conn, faulhaber::Port::Trace trace) {
  if (!active()) return trace;
  return [this, alive = alive_.watch(), conn, trace = std::move(trace)](const faulhaber::TraceEvent& e) {
    using K = faulhaber::TraceEvent::Kind;
    if (alive) {
      if (e.kind == K::rx) {
        request(lint::Link::faulhaber, conn, e.command != faulhaber::command::reset_node);
      } else if (e.kind == K::ignored) {
        reply(lint::Link::faulhaber, conn, lint::ReplyKind::none);
      } else if (e.kind == K::tx && e.command == faulhaber::command::statusword) {
        reply(lint::Link::faulhaber, 0, lint::ReplyKind::notification);
      } else if (e.kind == K::tx && e.command != faulhaber::command::emcy && e.command != faulhaber::command::boot) {
        reply(lint::Link::faulhaber, conn, lint::ReplyKind::response);
      }
    }
    if (trace) trace(e);
  };
}

void LintHub::od_write(const od::WriteNote& n) {
  if (!active()) return;
  lint::OdWrite w;
  w.time = now();
  w.conn = conn_;
  w.origin = n.origin;
  w.index = n.index;
  w.sub = n.sub;
  w.value = n.value;
  w.result = n.result;
  w.statusword_after = static_cast<std::uint16_t>(number(statusword_));
  w.mode_after = static_cast<std::int8_t>(number(mode_display_));
  w.helper = n.helper;
  engine_.observe(w);
  if (const auto m = lint::pdo_mapping_write(od_, w)) engine_.observe(*m);
}

void LintHub::core_event(const core::Event& e) {
  if (active()) engine_.observe(lint::CoreEvent{now(), e});
}

void LintHub::powered_on() {
  if (!active()) return;
  engine_.observe(lint::PowerOn{now(), static_cast<std::uint16_t>(number(statusword_)),
                                static_cast<std::uint16_t>(number(controlword_)),
                                static_cast<std::int8_t>(number(mode_)), number(target_velocity_)});
}

void LintHub::can_frame(const can::Frame& f, std::uint8_t node_id) {
  if (!active() || f.extended) return;
  engine_.observe(lint::classify_can_frame(od_, now(), conn_, f.id, f.rtr, f.dlc, f.data.data(), node_id));
}

void LintHub::can_sent(const can::Frame& f, std::uint8_t node_id) {
  if (!active() || f.extended || f.rtr || f.id != 0x580u + node_id || f.dlc < 1) return;
  engine_.observe(lint::SdoAnswer{now(), f.data[0]});
}

void LintHub::nmt(canopen::NmtState from, canopen::NmtState to) {
  if (active()) engine_.observe(lint::NmtChange{now(), static_cast<lint::Nmt>(from), static_cast<lint::Nmt>(to)});
}

void LintHub::request(lint::Link link, lint::Conn conn, bool expects_reply) {
  if (active()) engine_.observe(lint::ProtocolRequest{now(), link, conn, chunk_, expects_reply});
}

void LintHub::reply(lint::Link link, lint::Conn conn, lint::ReplyKind kind) {
  if (active()) engine_.observe(lint::ProtocolReply{now(), link, conn, kind});
}

void LintHub::closed(lint::Conn conn) {
  if (active()) engine_.observe(lint::ConnectionClosed{conn});
}

void LintHub::script_loop(lint::ScriptKind script, std::uint64_t statements_without_wait) {
  if (!active()) return;
  const auto n =
      statements_without_wait > UINT32_MAX ? UINT32_MAX : static_cast<std::uint32_t>(statements_without_wait);
  engine_.observe(lint::ScriptLoop{now(), script, n});
}

void LintHub::flash(lint::FlashKind kind, od::Origin origin) {
  if (active()) engine_.observe(lint::FlashWrite{now(), conn_, origin, kind});
}

}  // namespace mcemu::device
