#include "lint/engine.hpp"

#include "lint/cia402_rules.hpp"

namespace mcemu::lint {

Engine::Engine(Config config, Sink sink) : config_(std::move(config)), reporter_(config_) {
  reporter_.set_sink(std::move(sink));
  storage_.configure(config_);
  links_.configure(config_);
}

void Engine::configure(Config config) {
  config_ = std::move(config);
  reporter_.resize();
  storage_.configure(config_);
  links_.configure(config_);
}

Ms Engine::mono(Ms t) {
  if (t < last_drive_) offset_ += last_drive_ - t;
  last_drive_ = t;
  return t + offset_;
}

void Engine::observe(const OdWrite& w) {
  if (!active()) return;
  const At at{w.time, mono(w.time), w.conn, od::to_string(w.origin)};
  cia402_rules(w, view_, at, reporter_);
  if (w.origin != od::Origin::internal) {
    if (const auto kind = flash_kind_of(w)) storage_.on_flash(*kind, w.origin, view_, at, reporter_);
    // A FAULHABER controlword write (origin sdo) that changed the statusword: a notification follows.
    if (w.index == 0x6040 && w.sub == 0 && w.origin == od::Origin::sdo && accepted(w.result) &&
        w.statusword_after != view_.statusword) {
      links_.on_statusword_change_by(w.conn);
    }
  }
  view_.apply(w);
}

void Engine::observe(const CoreEvent& e) {
  if (!active()) return;
  mono(e.time);
  view_.apply(e);
}

void Engine::observe(const PowerOn& p) {
  if (!active()) return;
  mono(p.time);
  view_.apply(p);
  storage_.power_on();
  links_.power_on();
}

void Engine::observe(const NmtChange& n) {
  if (!active()) return;
  mono(n.time);
  canopen_.on_nmt(n);
}

void Engine::observe(const CanRequest& r) {
  if (!active()) return;
  canopen_.on_request(r, At{r.time, mono(r.time), r.conn, "canopen"}, reporter_);
}

void Engine::observe(const SdoAnswer& a) {
  if (!active()) return;
  mono(a.time);
  canopen_.on_answer(a);
}

void Engine::observe(const PdoMappingWrite& m) {
  if (!active()) return;
  canopen_.on_mapping(m, At{m.time, mono(m.time), m.conn, od::to_string(m.origin)}, reporter_);
}

void Engine::observe(const ProtocolRequest& r) {
  if (!active()) return;
  links_.on_request(r, At{r.time, mono(r.time), r.conn, to_string(r.link)}, reporter_);
}

void Engine::observe(const ProtocolReply& r) {
  if (!active()) return;
  links_.on_reply(r, At{r.time, mono(r.time), r.conn, to_string(r.link)}, reporter_);
}

void Engine::observe(const ConnectionClosed& c) {
  if (!active()) return;
  links_.on_closed(c.conn);
}

void Engine::observe(const ScriptLoop& s) {
  if (!active()) return;
  const At at{s.time, mono(s.time), 0, s.script == ScriptKind::code ? "script" : "basic"};
  storage_.on_script_loop(s, at, reporter_);
}

void Engine::observe(const FlashWrite& f) {
  if (!active()) return;
  storage_.on_flash(f.kind, f.origin, view_, At{f.time, mono(f.time), f.conn, od::to_string(f.origin)}, reporter_);
}

}  // namespace mcemu::lint
