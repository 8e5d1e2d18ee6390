#include "lint/storage_rules.hpp"

#include <string>

namespace mcemu::lint {

namespace {

constexpr std::int64_t k_save = 0x65766173;  // "save"
constexpr std::int64_t k_load = 0x64616F6C;  // "load"
constexpr Ms k_hour_ms = 3600000;

std::string_view name_of(FlashKind k) {
  switch (k) {
    case FlashKind::parameters: return "store (1010h)";
    case FlashKind::motor: return "motor store (3010h.01)";
    case FlashKind::factory_reset: return "factory reset (1011h)";
    case FlashKind::program: break;
  }
  return "program/variable save";
}

}  // namespace

std::optional<FlashKind> flash_kind_of(const OdWrite& w) {
  if (!accepted(w.result)) return std::nullopt;
  if (w.index == 0x1010 && w.sub >= 1 && w.sub <= 3 && w.value == k_save) return FlashKind::parameters;
  if (w.index == 0x1011 && w.sub >= 1 && w.sub <= 3 && w.value == k_load) return FlashKind::factory_reset;
  if (w.index == 0x3010 && w.sub == 1 && w.value == k_save) return FlashKind::motor;
  return std::nullopt;
}

void StorageRules::configure(const Config& c) {
  config_ = &c;
  stores_.clear();
  stores_.reserve(c.max_stores_per_hour);
  next_ = 0;
}

void StorageRules::on_flash(FlashKind kind, od::Origin origin, const DriveView& v, const At& at, Reporter& rep) {
  const std::size_t limit = config_->max_stores_per_hour;
  // The ring holds the last `limit` stores: when it is full and its oldest is less than an hour
  // old, this store is the (limit + 1)-th within an hour.
  if (stores_.size() == limit && at.mono - stores_[next_] < k_hour_ms) {
    rep.fire(RuleId::storage_store_rate, at, [&] {
      return std::string(name_of(kind)) + ": " + std::to_string(limit + 1) + " stores within " +
             std::to_string((at.mono - stores_[next_]) / 1000) + " s of drive time (limit " + std::to_string(limit) +
             " per hour)";
    });
  }
  if (stores_.size() < limit) {
    stores_.push_back(at.mono);
  } else {
    stores_[next_] = at.mono;
    next_ = (next_ + 1) % limit;
  }

  if (v.moving()) {
    rep.fire(RuleId::storage_store_while_moving, at,
             [&] { return std::string(name_of(kind)) + " while the axis moves (6041h bit 8)"; });
  }
  if (origin == od::Origin::script) {
    if (last_script_store_ && at.mono - *last_script_store_ < config_->script_flash_window_ms) {
      rep.fire(RuleId::script_flash_write_in_loop, at, [&] {
        return "script " + std::string(name_of(kind)) + " " + std::to_string(at.mono - *last_script_store_) +
               " ms after its previous store";
      });
    }
    last_script_store_ = at.mono;
  }
}

void StorageRules::on_script_loop(const ScriptLoop& s, const At& at, Reporter& rep) {
  const bool code = s.script == ScriptKind::code;
  const std::uint32_t limit = code ? config_->code_calls_without_wait : config_->basic_statements_without_wait;
  bool& armed = armed_[code ? 0 : 1];
  if (s.statements_without_wait < limit) {
    armed = true;  // it waited since the last finding
    return;
  }
  if (!armed) return;
  armed = false;
  rep.fire(RuleId::script_busy_loop, at, [&] {
    return std::string(code ? "MovingCap CODE script: " : "MC BASIC program: ") +
           std::to_string(s.statements_without_wait) + (code ? " drive calls" : " statements") +
           " without a wait (limit " + std::to_string(limit) + ")";
  });
}

void StorageRules::power_on() { armed_ = {true, true}; }

}  // namespace mcemu::lint
