#include "protocols/faulhaber/port.hpp"

#include <algorithm>
#include <deque>
#include <utility>
#include <vector>

#include "protocols/faulhaber/describe.hpp"

namespace mcemu::faulhaber {

struct Port::Registry {
  Port* port = nullptr;  // null once the port is gone
  std::vector<Session*> sessions;

  Session* find(std::uint64_t id) const;
};

// One connection: a receiver, the held-back output and the adapter's side (line::StreamSession).
class Port::Session final : public line::StreamSession, private Receiver::Sink {
 public:
  Session(std::shared_ptr<Registry> registry, std::uint64_t id, Millis timeout, Trace trace)
      : registry_(std::move(registry)), id_(id), receiver_(timeout), trace_(std::move(trace)) {
    registry_->sessions.push_back(this);
  }
  ~Session() override {
    auto& v = registry_->sessions;
    v.erase(std::remove(v.begin(), v.end(), this), v.end());
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  std::uint64_t id() const { return id_; }

  // line::StreamSession
  void receive(std::string_view bytes) override {
    Port* port = registry_->port;
    if (!port || stopped() || peer_closed_) return;  // nothing is read after FIN
    in_receive_ = true;
    receiver_.feed(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), port->now(), *this);
    in_receive_ = false;
  }
  std::string take_output() override {
    if (!registry_->port && !overflowed_) output_.clear();  // a session of a destroyed port is silent
    return std::exchange(output_, {});
  }
  void peer_closed() override {
    receiver_.reset();
    peer_closed_ = true;
  }
  bool finished() const override { return overflowed_ || !registry_->port || (peer_closed_ && held_.empty()); }
  void closing(std::string_view reason) override {
    trace_event(TraceEvent::Kind::event, {}, [reason](std::string& s) { s.append("closing: ").append(reason); });
  }

  // From the port.
  void queue_async(const Frame& f, Millis now) {
    if (stopped() || peer_closed_) return;
    queue(f, od::AbortCode::none, now, now);
  }
  void release(Millis now) {
    while (!held_.empty() && held_.front().ready && held_.front().due <= now) {
      Held h = std::move(held_.front());
      held_.pop_front();
      held_bytes_ -= h.frame.data.size() + 6;
      emit(h.frame, h.code);
    }
  }
  std::optional<Millis> next_due() const {
    if (held_.empty() || !held_.front().ready) return std::nullopt;
    return held_.front().due;
  }
  // The answer of a write the dictionary completed later (Store/Restore).
  void complete(std::uint64_t serial, Frame f, od::AbortCode code, Millis now, Millis delay) {
    if (stopped()) return;
    const auto it =
        std::find_if(held_.begin(), held_.end(), [&](const Held& h) { return !h.ready && h.serial == serial; });
    if (it == held_.end()) {  // inside the write call itself: on_frame() queues it
      early_.push_back({serial, now + delay, true, std::move(f), code});
      return;
    }
    it->frame = std::move(f);
    it->code = code;
    it->ready = true;
    it->due = now + delay;
    held_bytes_ += it->frame.data.size() + 6;
    release(now);
    check_limit();
  }
  bool wake_needed() const { return wake_needed_; }
  void do_wake() {
    wake_needed_ = false;
    wake();
  }

 private:
  struct Held {
    std::uint64_t serial = 0;  // of a pending write's placeholder
    Millis due{0};
    bool ready = true;  // false: a pending write's answer not there yet
    Frame frame;
    od::AbortCode code = od::AbortCode::none;
  };

  bool stopped() const { return overflowed_ || !registry_->port; }

  // Receiver::Sink
  bool check_crc() override { return registry_->port && registry_->port->crc_check(); }

  void on_dropped(const Dropped& d) override {
    trace_event(TraceEvent::Kind::dropped, d.bytes, [&d](std::string& s) {
      s.append(to_string(d.reason));
      if (d.count > d.bytes.size()) s.append(" (").append(std::to_string(d.count)).append(" bytes)");
    });
  }

  void on_frame(const FrameView& f, std::span<const std::uint8_t> raw) override {
    Port* port = registry_->port;
    if (!port || stopped()) return;
    trace_event(
        TraceEvent::Kind::rx, raw, [&f](std::string& s) { append_description(s, f, Direction::to_drive); }, f.command);
    const std::uint8_t node = port->node_id();
    if (f.node != node) {
      trace_event(TraceEvent::Kind::ignored, {}, [&](std::string& s) {
        s.append("for node ").append(std::to_string(f.node));
        s.append(", this drive is node ").append(std::to_string(node));
      });
      return;
    }
    const Millis now = port->now();
    const Millis delay = port->config_.response_delay;
    const std::uint64_t serial = next_serial_++;
    std::weak_ptr<Registry> weak = registry_;
    const std::uint64_t id = id_;
    const Commands::Later later = [weak, id, serial](Frame answer, od::AbortCode code) {
      const auto r = weak.lock();
      if (!r || !r->port) return;
      Session* s = r->find(id);
      if (!s) return;  // the connection is gone: its answer goes nowhere
      const Millis t = r->port->now();
      s->complete(serial, std::move(answer), code, t, r->port->config_.response_delay);
      r->port->wake_sessions();
    };
    Outcome o = port->commands_.handle(f, node, later);
    switch (o.kind) {
      case Outcome::Kind::respond: queue(o.response, o.code, now, now + delay); break;
      case Outcome::Kind::pending: hold_pending(serial, now); break;
      case Outcome::Kind::none: break;
    }
    if (o.reset_node && port->hooks_.reset_node) port->hooks_.reset_node();
    if (port->hooks_.after_request) port->hooks_.after_request();
  }

  void hold_pending(std::uint64_t serial, Millis now) {
    const auto it = std::find_if(early_.begin(), early_.end(), [&](const Held& h) { return h.serial == serial; });
    if (it != early_.end()) {
      Held h = std::move(*it);
      early_.erase(it);
      queue(h.frame, h.code, now, h.due);
      return;
    }
    held_.push_back({serial, now, false, {}, od::AbortCode::none});
  }

  // Output in order: straight out when nothing is held and it is due, else behind the held output.
  void queue(const Frame& f, od::AbortCode code, Millis now, Millis due) {
    if (held_.empty() && due <= now) {
      emit(f, code);
    } else {
      held_.push_back({0, due, true, f, code});
      held_bytes_ += f.data.size() + 6;
    }
    check_limit();
  }

  void emit(const Frame& f, od::AbortCode code) {
    append_encoded(output_, f.view());
    if (!in_receive_) wake_needed_ = true;  // receive()'s output is collected by the adapter anyway
    const std::size_t n = f.data.size() + 6;
    const std::span<const std::uint8_t> wire(reinterpret_cast<const std::uint8_t*>(output_.data()) + output_.size() - n,
                                             n);
    trace_event(
        TraceEvent::Kind::tx, wire,
        [&](std::string& s) {
          append_description(s, f.view(), Direction::to_host);
          if (f.command == command::controlword && code != od::AbortCode::none) {
            s.append(" 0x");
            append_hex(s, od::to_u32(code), 8);
          }
        },
        f.command);
  }

  void check_limit() {
    const Port* port = registry_->port;
    if (overflowed_ || !port || output_.size() + held_bytes_ <= port->config_.queue_limit_bytes) return;
    trace_event(TraceEvent::Kind::event, {}, [port](std::string& s) {
      s.append("closing: output queue above ").append(std::to_string(port->config_.queue_limit_bytes)).append(" bytes");
    });
    overflowed_ = true;
    // Everything goes to the adapter at once: its close-on-overflow rule closes the connection.
    for (const auto& h : held_) {
      if (h.ready) append_encoded(output_, h.frame.view());
    }
    held_.clear();
    held_bytes_ = 0;
    early_.clear();
    receiver_.reset();
    wake_needed_ = true;
  }

  // One trace line, its texts built in the session's reused buffers (no allocation per frame).
  template <class Text>
  void trace_event(TraceEvent::Kind kind, std::span<const std::uint8_t> bytes, const Text& text,
                   std::uint8_t frame_command = 0) {
    if (!trace_) return;
    trace_hex_.clear();
    append_hex(trace_hex_, bytes);
    trace_text_.clear();
    text(trace_text_);
    trace_({kind, trace_hex_, trace_text_, frame_command});
  }

  std::shared_ptr<Registry> registry_;
  std::uint64_t id_;
  Receiver receiver_;
  Trace trace_;
  std::string trace_hex_;  // reused buffers of the trace texts
  std::string trace_text_;
  std::string output_;
  std::deque<Held> held_;
  std::size_t held_bytes_ = 0;
  std::vector<Held> early_;
  std::uint64_t next_serial_ = 1;
  bool in_receive_ = false;
  bool wake_needed_ = false;
  bool peer_closed_ = false;
  bool overflowed_ = false;
};

Port::Session* Port::Registry::find(std::uint64_t id) const {
  for (auto* s : sessions) {
    if (s->id() == id) return s;
  }
  return nullptr;
}

Port::Port(od::ObjectDictionary& od, PortConfig config, Hooks hooks)
    : od_(od),
      config_(config),
      hooks_(std::move(hooks)),
      commands_(od),
      registry_(std::make_shared<Registry>()),
      node_id_(od.find(k_rs232_index, k_node_id_sub)),
      settings_(od.find(k_rs232_index, k_settings_sub)),
      net_mode_(od.find(k_rs232_index, k_net_mode_sub)) {
  registry_->port = this;
}

Port::~Port() {
  registry_->port = nullptr;
  registry_->sessions.clear();
}

void trace_line(const TraceEvent& e, std::string& out) {
  out.clear();
  if (e.kind == TraceEvent::Kind::dropped) out += "dropped ";
  if (e.kind == TraceEvent::Kind::ignored) out += "ignored ";
  out += e.hex;
  if (!e.hex.empty() && !e.summary.empty()) out += " | ";
  out += e.summary;
}

std::unique_ptr<line::StreamSession> Port::make_session(Trace trace) {
  return std::make_unique<Session>(registry_, next_session_id_++, config_.inter_byte_timeout, std::move(trace));
}

Millis Port::now() const { return hooks_.now ? hooks_.now() : last_step_; }

std::uint8_t Port::node_id() const {
  return node_id_ ? static_cast<std::uint8_t>(od_.number(*node_id_)) : k_default_node_id;
}

std::uint32_t Port::settings() const {
  return settings_ ? static_cast<std::uint32_t>(od_.number(*settings_)) : k_default_settings;
}

bool Port::crc_check() const { return (settings() & k_ignore_crc_bit) == 0; }
bool Port::net_mode() const { return net_mode_ && od_.number(*net_mode_) != 0; }
bool Port::emcy_enabled() const { return !net_mode() && (settings() & k_emcy_bit) != 0; }
bool Port::async_enabled() const { return !net_mode() && (settings() & k_async_bit) != 0; }
std::size_t Port::session_count() const { return registry_->sessions.size(); }

void Port::notify_statusword(std::uint16_t statusword) {
  if (async_enabled()) broadcast(statusword_notification(node_id(), statusword));
}

void Port::notify_emcy(std::uint16_t code, std::uint8_t error_register, std::uint16_t error_word) {
  if (emcy_enabled()) broadcast(emcy_notification(node_id(), code, error_register, error_word));
}

void Port::send_boot() {
  if (!async_enabled()) return;
  std::string name;
  if (const auto r = od_.read_bytes(0x1008, 0)) {
    for (const auto b : *r) name.push_back(static_cast<char>(b));
  }
  broadcast(boot_message(node_id(), name));
}

void Port::broadcast(const Frame& f) {
  const Millis t = now();
  for (auto* s : registry_->sessions) s->queue_async(f, t);
  wake_sessions();
}

void Port::wake_sessions() {
  // A wake-up lets the adapter write, or close the connection (overflow), which may destroy the
  // session and others: each one is looked up again before its wake-up.
  std::vector<std::uint64_t> ids;
  for (const auto* s : registry_->sessions) {
    if (s->wake_needed()) ids.push_back(s->id());
  }
  const auto registry = registry_;  // a wake-up may even destroy the port
  for (const auto id : ids) {
    if (Session* s = registry->find(id)) s->do_wake();
  }
}

std::optional<Millis> Port::next_deadline() const {
  std::optional<Millis> next;
  for (const auto* s : registry_->sessions) {
    if (const auto due = s->next_due(); due && (!next || *due < *next)) next = due;
  }
  return next;
}

void Port::step(Millis now) {
  last_step_ = std::max(last_step_, now);
  for (auto* s : registry_->sessions) s->release(now);
  wake_sessions();
}

}  // namespace mcemu::faulhaber
