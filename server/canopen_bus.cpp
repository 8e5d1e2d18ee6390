#include "server/canopen_bus.hpp"

#include <algorithm>

#include "protocols/canopen/dynamic_mapping.hpp"
#include "protocols/slcan/session.hpp"

namespace mcemu::server {

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

std::unique_ptr<line::StreamSession> CanopenBus::make_session() {
  std::weak_ptr<Registry> weak = registry_;
  auto inner = std::make_unique<slcan::Session>(
      slcan_,
      [weak](const can::Frame& f) {
        if (auto r = weak.lock(); r && r->bus) r->bus->from_client(f);
      },
      [weak]() -> std::uint32_t {
        auto r = weak.lock();
        if (!r || !r->bus) return 0;
        const auto h = r->bus->od_.find(0x3404, 4);
        return h ? static_cast<std::uint32_t>(r->bus->od_.number(*h)) : 0u;
      });
  registry_->sessions.push_back(inner.get());
  return std::make_unique<BusSession>(registry_, std::move(inner));
}

void CanopenBus::power_on() {
  powered_at_ = now_;
  node_->power_on(now_);
}

void CanopenBus::start() {
  power_on();
  for (int guard = 0; guard < 100000 && node_->state() == canopen::NmtState::initialising; ++guard) step();
}

void CanopenBus::step(std::chrono::milliseconds dt) {
  now_ += dt;
  broadcast(node_->advance(now_));
}

void CanopenBus::from_client(const can::Frame& frame) { broadcast(node_->on_frame(frame, now_)); }

void CanopenBus::broadcast(const std::vector<can::Frame>& frames) {
  // A session may be destroyed by a write error only asynchronously, never inside deliver().
  const auto stamp = now_ - powered_at_;
  for (const auto& f : frames) {
    for (auto* s : registry_->sessions) s->deliver(f, stamp);
  }
}

}  // namespace mcemu::server
