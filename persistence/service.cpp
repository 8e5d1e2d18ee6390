#include "persistence/service.hpp"

#include <algorithm>

namespace mcemu::persistence {

namespace {

std::int64_t get_number(const od::Value& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}

// Replaces the values of `group` in `target` with those of `source` (the first of equal keys in
// `source`, which holds each key once when it comes from a snapshot or a file).
void take_group(Image& target, const Image& source, Group group, const od::ObjectDictionary& od) {
  const auto key = [](const od::StoredValue& sv) { return (std::uint32_t{sv.index} << 8) | sv.sub; };
  std::vector<const od::StoredValue*> by_key;
  by_key.reserve(source.objects.size());
  for (const auto& src : source.objects) by_key.push_back(&src);
  std::stable_sort(by_key.begin(), by_key.end(), [&](const auto* a, const auto* b) { return key(*a) < key(*b); });
  for (auto& sv : target.objects) {
    const auto* info = od.info(sv.index, sv.sub);
    if (!info || group_of(*info) != group) continue;
    const auto it = std::lower_bound(by_key.begin(), by_key.end(), key(sv),
                                     [&](const od::StoredValue* p, std::uint32_t k) { return key(*p) < k; });
    if (it != by_key.end() && key(**it) == key(sv)) sv.value = (*it)->value;
  }
}

}  // namespace

Service::Service(od::ObjectDictionary& od, std::string model, std::string mcemu_version, std::function<Image()> factory,
                 std::optional<Image> on_file, Storage& storage, ServiceHooks hooks)
    : od_(od),
      model_(std::move(model)),
      version_(std::move(mcemu_version)),
      make_factory_(std::move(factory)),
      durable_(std::move(on_file)),
      expected_(durable_),
      storage_(storage),
      hooks_(std::move(hooks)) {
  if (durable_) script_ = durable_->script;
  // 5006h (MovingCap store counters) exists on the MovingCap models only; without it nothing is counted.
  if (const auto c = od_.read_number(0x5006, 5)) next_counter_ = *c;
  for (std::uint8_t s = 1; s <= 3; ++s) {
    od_.on_write(0x1010, s, [this](od::WriteRequest& r) { return store_all(r); });
    od_.on_write(0x1011, s, [this](od::WriteRequest& r) { return restore_all(r); });
  }
  if (od_.find(0x3010, 1)) od_.on_write(0x3010, 1, [this](od::WriteRequest& r) { return store_motor(r); });
}

const Image& Service::factory() const {
  if (!factory_) factory_ = make_factory_();
  return *factory_;
}

Image Service::with_counter(Image img) {
  ++next_counter_;
  for (auto& sv : img.objects) {
    if (sv.index == 0x5006 && sv.sub == 5) sv.value = next_counter_;
  }
  return img;
}

void Service::count_event(bool ok) {
  if (!od_.find(0x5006, 1)) return;
  const auto bump = [&](std::uint8_t sub) {
    const auto h = od_.handle(0x5006, sub);
    od_.set(h, od::Value{(od_.number(h) + 1) & 0xFF});
  };
  bump(3);
  if (!ok) bump(4);
  od_.set(od_.handle(0x5006, 1), od::Value{std::int64_t{ok ? 1 : 0}});
}

void Service::submit(Image img, od::Done done, std::function<void(bool ok)> after) {
  const std::string text = serialize(img, model_, version_, hooks_.now_utc ? hooks_.now_utc() : "");
  const std::int64_t counter = next_counter_;
  expected_ = img;
  ++in_flight_;
  storage_.write_state(text, [this, alive = alive_.watch(), img = std::move(img), done = std::move(done),
                              after = std::move(after), counter](std::optional<std::string> error) mutable {
    if (!alive) return;  // the drive is gone: nothing to update, nobody to answer
    --in_flight_;
    if (error) {
      if (hooks_.log_error) hooks_.log_error("store failed: " + *error);
      --next_counter_;
      expected_ = durable_;
      count_event(false);
      if (after) after(false);
      if (done) done(od::AbortCode::hardware_error);
      return;
    }
    durable_ = std::move(img);
    if (const auto h = od_.find(0x5006, 5); h && counter > od_.number(*h)) od_.set(*h, od::Value{counter});
    count_event(true);
    if (after) after(true);
    if (done) done(od::AbortCode::none);
  });
}

od::AbortCode Service::store_all(od::WriteRequest& req) {
  if (get_number(req.value) != k_save) return od::AbortCode::cannot_store;
  Image img = snapshot(od_);
  img.home_offset_inc = hooks_.home_offset_inc ? hooks_.home_offset_inc() : 0;
  img.script = script_;
  submit(with_counter(std::move(img)), std::move(*req.done), {});
  return od::AbortCode::pending;
}

od::AbortCode Service::store_motor(od::WriteRequest& req) {
  if (get_number(req.value) != k_save) return od::AbortCode::cannot_store;
  Image img = expected_ ? *expected_ : factory();
  take_group(img, snapshot(od_), Group::motor, od_);
  submit(with_counter(std::move(img)), std::move(*req.done),
         [this](bool ok) { od_.set(od_.handle(0x3010, 2), od::Value{std::int64_t{ok ? 1 : 0}}); });
  return od::AbortCode::pending;
}

od::AbortCode Service::restore_all(od::WriteRequest& req) {
  if (get_number(req.value) != k_load) return od::AbortCode::cannot_store;
  if (hooks_.operation_enabled && hooks_.operation_enabled()) return od::AbortCode::device_state;
  Image img = factory();
  // Survivors: the motor group and the network identity keep their stored values (or factory
  // values if never stored).
  const Image& kept = expected_ ? *expected_ : factory();
  take_group(img, kept, Group::motor, od_);
  take_group(img, kept, Group::network, od_);
  img.home_offset_inc = 0;
  img.autostart = false;
  img.script = nullptr;
  submit(with_counter(std::move(img)), std::move(*req.done), [this](bool ok) {
    if (!ok) return;
    std::vector<od::StoredValue> params;
    for (const auto& sv : factory().objects) {
      const auto* info = od_.info(sv.index, sv.sub);
      if (info && group_of(*info) == Group::parameters) params.push_back(sv);
    }
    od_.load_values(params);
    script_ = nullptr;
    if (hooks_.reset_script) hooks_.reset_script();
    if (hooks_.after_restore) hooks_.after_restore();
    if (hooks_.log_info) hooks_.log_info("factory reset done: parameters restored, script replaced by the placeholder");
  });
  return od::AbortCode::pending;
}

}  // namespace mcemu::persistence
