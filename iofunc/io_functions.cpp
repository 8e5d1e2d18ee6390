// IoFunctions: hooks, the inputs observer, the order of one step (iofunc.md §3) and the output
// side (§2.2, §5). The input functions themselves are in input_functions.cpp.
#include "iofunc/io_functions.hpp"

#include <algorithm>

namespace mcemu::iofunc {
namespace {

constexpr std::uint32_t k_output_mask = 0x000F0000;  // OUT1 … OUT4 = bits 16 … 19

constexpr std::uint32_t input_bit(int n) { return 1u << (15 + n); }
constexpr std::uint32_t output_bit(std::size_t k) { return 1u << (16 + k); }

std::int64_t as_int(const od::Value& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}

std::string hex(std::uint64_t v, int digits) {
  static constexpr char k_digits[] = "0123456789ABCDEF";
  std::string out(static_cast<std::size_t>(digits), '0');
  for (int i = digits - 1; i >= 0; --i, v >>= 4) out[static_cast<std::size_t>(i)] = k_digits[v & 0xF];
  return out;
}

}  // namespace

IoFunctions::IoFunctions(od::ObjectDictionary& od, core::DriveCore& core)
    : od_(od), core_(core), h_(IoHandles::resolve(od)) {
  install_hooks();
  core_.set_inputs_observer(
      [this](std::uint32_t old_word, std::uint32_t new_word) { on_inputs_changed(old_word, new_word); });
  reset_volatile();
}

void IoFunctions::install_hooks() {
  od_.on_write(0x3510, 2, [this](od::WriteRequest& req) {
    // the OD validator has checked YYZZh already; ZZ = 0 is an accepted no-op (§4.13)
    const std::int64_t v = as_int(req.value);
    const int function = static_cast<int>(v & 0xFF);
    if (function != 0) queue_.push_back(Event{EventKind::command, static_cast<int>((v >> 8) & 0xFF), function});
    return od::AbortCode::none;
  });
  for (int n = 1; n <= 10; ++n) {
    od_.on_write(static_cast<std::uint16_t>(0x3510 + n), 1, [this, n](od::WriteRequest&) {
      on_function_written(n);
      return od::AbortCode::none;
    });
  }
  od_.on_write(0x60FE, 1, [this](od::WriteRequest& req) {
    // only manual outputs take the written bits; the stored word is the composed one (§2.2)
    const auto& masks = output_masks();
    const std::uint32_t manual = masks.all & ~masks.owned;
    const auto written = static_cast<std::uint32_t>(as_int(req.value));
    if (((written ^ compose()) & k_output_mask & ~manual) != 0 && req.origin != od::Origin::internal) {
      note(core::DiagnosticLevel::debug, "60FEh.01: outputs owned by an output function keep their level");
    }
    latch_ = written & manual;
    req.value = od::Value{static_cast<std::int64_t>(compose())};
    return od::AbortCode::none;
  });
  for (std::size_t k = 0; k < h_.out.size(); ++k) {
    od_.on_write(static_cast<std::uint16_t>(0x3611 + k), 1, [this, k](od::WriteRequest& req) {
      const bool was_owned = as_int(req.stored) != 0;
      const bool owned = as_int(req.value) != 0;
      const std::uint32_t bit = output_bit(k);
      // switched on: keep the present level until the next step; switched off: the output goes low
      if (owned && !was_owned) levels_ = (levels_ & ~bit) | (compose() & bit);
      if (owned != was_owned) latch_ &= ~bit;
      return od::AbortCode::none;
    });
  }
  // After the store, entries whose new value changes what the core or the outputs compute: the
  // virtual inputs (§2.1) and 60FEh (a combined pin may have changed); an output function switched.
  od_.on_change({{0x3510, 1}, {0x60FE, 1}}, [this](const od::EntryInfo&, const od::Value&) { recompute_inputs(); });
  od_.on_change({{0x3611, 1}, {0x3612, 1}, {0x3613, 1}, {0x3614, 1}},
                [this](const od::EntryInfo&, const od::Value&) { write_outputs(); });
}

void IoFunctions::recompute_inputs() { core_.recompute_inputs(); }

// The observer only queues (drive-core.md §1.5): one event per changed bit, ascending n.
void IoFunctions::on_inputs_changed(std::uint32_t old_word, std::uint32_t new_word) {
  for (int n = 1; n <= 10; ++n) {
    const std::uint32_t bit = input_bit(n);
    if (((old_word ^ new_word) & bit) == 0) continue;
    queue_.push_back(Event{(new_word & bit) ? EventKind::rising : EventKind::falling, n, 0});
  }
}

void IoFunctions::reset_volatile() {
  queue_.clear();
  timers_ = {};
  jog_owner_.reset();
  executed_ = 0;
  view_ = static_cast<std::uint32_t>(num(h_.inputs));
  levels_ = static_cast<std::uint32_t>(num(h_.outputs)) & k_output_mask;
  latch_ = levels_;
  for (std::size_t k = 0; k < h_.out.size(); ++k) {
    if (num(h_.out[k].function) != 0) latch_ &= ~output_bit(k);
  }
}

void IoFunctions::power_on(const core::PowerOnState& state) {
  core_.power_on(state);
  reset_volatile();
}

void IoFunctions::after_bulk_load() {
  core_.reload_parameters();
  timers_ = {};
  jog_owner_.reset();
  executed_ = 0;
  // functions may have changed without hooks: an output that is manual now keeps only its latch
  for (std::size_t k = 0; k < h_.out.size(); ++k) {
    if (num(h_.out[k].function) != 0) latch_ &= ~output_bit(k);
  }
  write_outputs();
}

void IoFunctions::step() {
  const std::uint64_t now = core_.time_ms();
  check_enable_loss();
  apply_events(now);  // 1
  fire_timers(now);   // 2
  core_.step();       // 3
  if (jog_owner_ && num(h_.mode_display) != 3) jog_owner_.reset();
  update_outputs();  // 4 (5: edges arrive through the observer)
}

void IoFunctions::step(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) step();
}

std::uint64_t IoFunctions::quiet_steps() const {
  if (!queue_.empty()) return 0;
  if (jog_owner_ && num(h_.mode_display) != 3) return 0;  // released in the next step
  std::uint64_t q = core_.quiet_steps();
  // a timer fires in the step that starts at its deadline (fire_timers before the core's step)
  const std::uint64_t now = core_.time_ms();
  for (const auto& t : timers_) {
    if (t) q = std::min(q, t->deadline > now ? t->deadline - now : 0);
  }
  return q;
}

// Losing Software Enable in SO, OE or QSA clears timers and jog ownership (§4.11), in the tick in
// which the core acts on it.
void IoFunctions::check_enable_loss() {
  const core::PdsState s = core_.state();
  const bool powered = s == core::PdsState::switched_on || s == core::PdsState::operation_enabled ||
                       s == core::PdsState::quick_stop_active;
  if (!powered || core_.software_enabled()) return;
  const bool pending = jog_owner_ || std::any_of(timers_.begin(), timers_.end(), [](const auto& t) { return t; });
  if (!pending) return;
  cancel_all();
  note(core::DiagnosticLevel::info, "software enable lost: pending input functions cancelled");
}

void IoFunctions::apply_events(std::uint64_t now) {
  std::vector<Event> events;
  events.swap(queue_);
  for (const Event& e : events) {
    switch (e.kind) {
      case EventKind::rising:
      case EventKind::falling: {
        const bool rising = e.kind == EventKind::rising;
        view_ = rising ? (view_ | input_bit(e.input)) : (view_ & ~input_bit(e.input));
        dispatch_edge(e.input, rising, now);
        break;
      }
      case EventKind::command: dispatch_command(e.input, e.function, now); break;
    }
  }
}

void IoFunctions::fire_timers(std::uint64_t now) {
  std::vector<std::pair<std::uint64_t, int>> due;  // (deadline, input): deadline order, ties by input
  for (int n = 1; n <= 10; ++n) {
    const auto& t = timers_[static_cast<std::size_t>(n - 1)];
    if (t && t->deadline <= now) due.emplace_back(t->deadline, n);
  }
  std::sort(due.begin(), due.end());
  for (const auto& [deadline, n] : due) {
    auto& t = timers_[static_cast<std::size_t>(n - 1)];
    if (!t || t->deadline != deadline) continue;  // cancelled by an earlier one
    const int function = t->function;
    t.reset();
    (this->*function_row(function)->act)(n);
  }
}

// ---- outputs (§2.2, §5)

OutputConfig IoFunctions::output_config(std::size_t k) const {
  const OutputRecord& r = h_.out[k];
  OutputConfig c;
  c.function = static_cast<int>(num(r.function));
  c.config = static_cast<std::uint16_t>(num(r.config));
  c.right_position = num(r.right_position);
  c.left_position = num(r.left_position);
  c.right_distance = num(r.right_distance);
  c.left_distance = num(r.left_distance);
  return c;
}

DriveSnapshot IoFunctions::snapshot() const {
  DriveSnapshot s;
  s.statusword = static_cast<std::uint16_t>(num(h_.statusword));
  s.mfr_status = static_cast<std::uint32_t>(num(h_.mfr_status));
  s.position_user = num(h_.position_user);
  s.position_inc = num(h_.position_inc);
  const std::int64_t option = num(h_.position_option);
  switch (option & 0x3) {
    case 0: s.general_reference_inc = core_.last_internal_target_inc(); break;
    case 1: s.general_reference_inc = num(h_.demand_inc); break;
    default: s.general_reference_inc = s.position_inc; break;
  }
  if (option & 0xC0) {
    // the rotary range of drive-core.md §7.11: 607Dh when the limits are on, else one revolution
    const std::int64_t low = num(h_.limit_min);
    const std::int64_t high = num(h_.limit_max);
    const bool limits = !(low == 0 && high == 0) && low < high;
    const core::Scaling& sc = core_.scaling();
    s.rotary_period_inc = sc.distance_to_inc(limits ? high - low : sc.revolution_user());
  }
  for (int n = 1; n <= 10; ++n) s.result1[static_cast<std::size_t>(n - 1)] = num(record(n).result1);
  s.candidates = feedback_candidates();
  return s;
}

void IoFunctions::update_outputs() {
  // The snapshot (~25 reads) only when an output function owns an output: most drives have none.
  std::optional<DriveSnapshot> s;
  std::uint32_t levels = 0;
  const std::uint32_t owned = output_masks().owned;
  for (std::size_t k = 0; k < h_.out.size(); ++k) {
    if ((owned & output_bit(k)) == 0) continue;
    if (!s) s = snapshot();
    if (output_level(output_config(k), static_cast<int>(k + 1), *s, core_.scaling())) levels |= output_bit(k);
  }
  levels_ = levels;
  write_outputs();
}

std::uint32_t IoFunctions::compose() const {
  const auto& m = output_masks();
  return (levels_ & m.owned) | (latch_ & m.all & ~m.owned);
}

const IoFunctions::OutputMasks& IoFunctions::output_masks() const {
  return output_masks_.get(od_, [this] {
    OutputMasks m;
    for (std::size_t k = 0; k < h_.out.size(); ++k) {
      m.all |= output_bit(k);
      if (num(h_.out[k].function) != 0) m.owned |= output_bit(k);
    }
    return m;
  });
}

void IoFunctions::write_outputs() {
  const std::uint32_t word = compose();
  if (static_cast<std::uint32_t>(num(h_.outputs)) != word) put(h_.outputs, word);
}

std::uint16_t IoFunctions::feedback_candidates() const {
  std::uint16_t mask = executed_;
  for (int n = 1; n <= 10; ++n) {
    const std::int64_t code = num(record(n).function);
    const std::int64_t hi = (code >> 8) & 0xFF;
    const std::int64_t lo = code & 0xFF;
    if (hi == 4 || hi == 6 || lo == 4 || lo == 6) mask |= static_cast<std::uint16_t>(1u << (n - 1));
  }
  return mask;
}

// ---- queries and diagnostics

bool IoFunctions::teach_active() const {
  for (int n = 1; n <= 10; ++n) {
    const std::int64_t code = num(record(n).function);
    if ((((code >> 8) & 0xFF) == 8 || (code & 0xFF) == 8) && (view_ & input_bit(n))) return true;
  }
  return false;
}

std::optional<std::uint64_t> IoFunctions::timer_deadline(int input) const {
  if (input < 1 || input > 10) return std::nullopt;
  const auto& t = timers_[static_cast<std::size_t>(input - 1)];
  if (!t) return std::nullopt;
  return t->deadline;
}

std::vector<Diagnostic> IoFunctions::drain_diagnostics() {
  std::vector<Diagnostic> out;
  out.swap(diagnostics_);
  return out;
}

void IoFunctions::note(core::DiagnosticLevel level, std::string text) {
  diagnostics_.push_back(Diagnostic{level, std::move(text)});
}

void IoFunctions::put(od::Handle h, std::int64_t v) {
  const od::AbortCode c = od_.set(h, od::Value{v});
  if (c == od::AbortCode::none) return;
  const od::EntryInfo& info = od_.info(h);
  note(core::DiagnosticLevel::warning, "internal write of " + hex(info.index, 4) + "h." + hex(info.sub, 2) +
                                           "h refused: abort " + hex(od::to_u32(c), 8) + "h");
}

}  // namespace mcemu::iofunc
