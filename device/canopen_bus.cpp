#include "device/canopen_bus.hpp"

#include <algorithm>

#include "drive/od/objects.hpp"
#include "protocols/canopen/dynamic_mapping.hpp"
#include "protocols/slcan/codec.hpp"
#include "protocols/slcan/session.hpp"

namespace mcemu::device {

namespace {

std::string frame_text(const can::Frame& f) {
  std::string line = slcan::encode_frame(f, std::nullopt);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return "frame " + line;
}

}  // namespace

struct CanopenBus::Registry {
  CanopenBus* bus = nullptr;  // null once the bus is gone
  std::vector<slcan::Session*> sessions;
};

// The session the line adapter owns: an SLCAN session that leaves the bus when the connection ends.
class CanopenBus::BusSession final : public line::StreamSession {
 public:
  BusSession(std::shared_ptr<Registry> registry, std::unique_ptr<slcan::Session> inner)
      : registry_(std::move(registry)), inner_(std::move(inner)) {
    inner_->set_wake([this] { wake(); });
  }
  ~BusSession() override {
    auto& v = registry_->sessions;
    v.erase(std::remove(v.begin(), v.end(), inner_.get()), v.end());
  }
  BusSession(const BusSession&) = delete;
  BusSession& operator=(const BusSession&) = delete;

  void receive(std::string_view bytes) override { inner_->receive(bytes); }
  std::string take_output() override { return inner_->take_output(); }
  void peer_closed() override { inner_->peer_closed(); }
  bool finished() const override { return inner_->finished(); }

 private:
  std::shared_ptr<Registry> registry_;
  std::unique_ptr<slcan::Session> inner_;
};

CanopenBus::CanopenBus(od::ObjectDictionary& od, slcan::SlcanConfig slcan, canopen::CanopenConfig canopen,
                       canopen::Node::Hooks hooks)
    : od_(od),
      slcan_(std::move(slcan)),
      dynamic_mapping_(canopen.dynamic_pdo_mapping ? std::make_unique<canopen::DynamicMapping>(od) : nullptr),
      node_(std::make_unique<canopen::Node>(od, canopen, std::move(hooks))),
      registry_(std::make_shared<Registry>()) {
  registry_->bus = this;
}

CanopenBus::~CanopenBus() {
  registry_->bus = nullptr;
  registry_->sessions.clear();
}

std::size_t CanopenBus::session_count() const { return registry_->sessions.size(); }

std::unique_ptr<line::StreamSession> CanopenBus::make_session(slcan::Session::Trace trace) {
  std::weak_ptr<Registry> weak = registry_;
  auto inner = std::make_unique<slcan::Session>(
      slcan_,
      [weak](const can::Frame& f) {
        if (auto r = weak.lock(); r && r->bus) r->bus->from_client(f);
      },
      [weak]() -> std::uint32_t {
        auto r = weak.lock();
        if (!r || !r->bus) return 0;
        const auto h = r->bus->od_.find(od::k_device_info, od::k_device_info_serial);
        return h ? static_cast<std::uint32_t>(r->bus->od_.number(*h)) : 0u;
      });
  inner->set_trace(std::move(trace));
  inner->set_bel_fault([weak] {
    auto r = weak.lock();
    return r && r->bus && r->bus->faults_.bel && r->bus->faults_.bel();
  });
  registry_->sessions.push_back(inner.get());
  return std::make_unique<BusSession>(registry_, std::move(inner));
}

void CanopenBus::power_on() {
  const auto before = node_->state();
  powered_at_ = now_;
  node_->power_on(now_);
  nmt_since(before);
}

void CanopenBus::nmt_since(canopen::NmtState before) {
  if (observer_.nmt && node_->state() != before) observer_.nmt(before, node_->state());
}

void CanopenBus::start() {
  power_on();
  for (int guard = 0; guard < 100000 && node_->state() == canopen::NmtState::initialising; ++guard) step();
}

void CanopenBus::step(std::chrono::milliseconds dt) {
  now_ += dt;
  const auto before = node_->state();
  auto frames = node_->advance(now_);
  nmt_since(before);
  broadcast(frames);
}

void CanopenBus::from_client(const can::Frame& frame) {
  if (observer_.client_frame) observer_.client_frame(frame);
  const auto before = node_->state();
  auto frames = node_->on_frame(frame, now_);
  nmt_since(before);
  broadcast(frames);
}

void CanopenBus::broadcast(const std::vector<can::Frame>& frames) {
  const auto stamp = now_ - powered_at_;
  for (const auto& f : frames) {
    if (observer_.node_frame) observer_.node_frame(f);
    const auto v = faults_.node_frame ? faults_.node_frame(f) : device::Verdict{};
    if (v.action == device::Verdict::Action::drop) {
      if (faults_.trace) faults_.trace(device::verdict_text(v, frame_text(f)));
      continue;
    }
    const auto wall = faults_.wall_now ? faults_.wall_now() : std::chrono::milliseconds(0);
    const bool was_empty = delayed_.empty();
    if (v.action == device::Verdict::Action::delay && faults_.trace) {
      faults_.trace(device::verdict_text(v, frame_text(f)));
    }
    if (auto now = delayed_.push(Stamped{f, stamp}, wall, wall + v.delay)) {
      deliver(*now);
    } else if (was_empty && faults_.schedule) {
      faults_.schedule(*delayed_.next_due());
    }
  }
}

void CanopenBus::deliver(const Stamped& f) {
  // A session may be destroyed by a write error only asynchronously, never inside deliver().
  for (auto* s : registry_->sessions) s->deliver(f.frame, f.stamp);
}

void CanopenBus::release_delayed() {
  const auto wall = faults_.wall_now ? faults_.wall_now() : std::chrono::milliseconds(0);
  for (const auto& f : delayed_.pop_due(wall)) deliver(f);
  if (const auto due = delayed_.next_due(); due && faults_.schedule) faults_.schedule(*due);
}

void CanopenBus::send_raw(std::string_view text) {
  for (auto* s : registry_->sessions) s->send_raw(text);
}

}  // namespace mcemu::device
