#include "scripting/basic/programs.hpp"

#include <utility>

namespace mcemu::basic {

std::string_view to_string(SlotState s) {
  switch (s) {
    case SlotState::empty: return "empty";
    case SlotState::loaded: return "loaded";
    case SlotState::running: return "running";
    case SlotState::stopped: return "stopped";
    case SlotState::error: return "error";
  }
  return "?";
}

Programs::Programs(od::ObjectDictionary& od, VariableStorage& storage, Settings settings, EventSink sink)
    : sink_(std::move(sink)), interp_(od, storage, std::move(settings), [this](const Event& e) { on_event(e); }) {}

// A run that ends (request, end of text, error) leaves its state in the slot.
void Programs::on_event(const Event& e) {
  if (valid(e.slot)) {
    SlotStatus& st = at(e.slot).status;
    switch (e.kind) {
      case EventKind::stopped:
      case EventKind::finished:
        st.state = SlotState::stopped;
        st.line = 0;
        st.message.clear();
        st.code = od::AbortCode::none;
        break;
      case EventKind::error:
        st.state = SlotState::error;
        st.line = e.line;
        st.message = e.message;
        st.code = e.code;
        st.load_error = false;
        break;
      default: break;
    }
  }
  if (sink_) sink_(e);
}

Programs::Upload Programs::upload(int slot, std::string_view text) {
  if (!valid(slot)) return Upload::bad_slot;
  if (text.size() > k_max_program_bytes) return Upload::too_large;
  if (running() == slot) interp_.stop("replaced by an upload");
  Slot& s = at(slot);
  s.source.assign(text);
  s.program.reset();
  s.status = SlotStatus{.bytes = text.size()};
  auto result = load(s.source);
  if (auto* err = std::get_if<LoadError>(&result)) {
    s.status.state = SlotState::error;
    s.status.line = err->line;
    s.status.message = std::move(err->message);
    s.status.load_error = true;
  } else {
    s.program = std::move(std::get<Program>(result));
    s.status.state = SlotState::loaded;
  }
  return Upload::ok;
}

bool Programs::erase(int slot) {
  if (!valid(slot)) return false;
  if (running() == slot) interp_.stop("erased");
  at(slot) = Slot{};
  return true;
}

Programs::Start Programs::start(int slot) {
  if (!valid(slot)) return Start::bad_slot;
  Slot& s = at(slot);
  const SlotState st = s.status.state;
  if (!s.program || !(st == SlotState::loaded || st == SlotState::stopped)) return Start::not_startable;
  if (running() != 0) interp_.stop("slot " + std::to_string(slot) + " started");
  interp_.start(*s.program, slot);
  return Start::ok;
}

void Programs::stop() { interp_.stop(); }

SlotStatus Programs::status(int slot) const {
  if (!valid(slot)) return SlotStatus{};
  SlotStatus st = at(slot).status;
  if (running() == slot) st.state = SlotState::running;
  return st;
}

std::string_view Programs::source(int slot) const { return valid(slot) ? std::string_view(at(slot).source) : ""; }

int Programs::running() const { return interp_.running() ? interp_.slot() : 0; }

std::optional<std::uint32_t> Programs::running_line() const {
  return interp_.running() ? interp_.line() : std::nullopt;
}

bool Programs::set_autostart(int slot) {
  if (slot != 0 && !valid(slot)) return false;
  autostart_ = slot;
  return true;
}

void Programs::power_cycle() {
  interp_.stop("power cycle");
  for (auto& s : slots_) {
    if (s.program) s.status = SlotStatus{.state = SlotState::loaded, .bytes = s.source.size()};
  }
}

bool Programs::start_autostart() { return autostart_ != 0 && start(autostart_) == Start::ok; }

}  // namespace mcemu::basic
