#include "scripting/basic/interpreter.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace mcemu::basic {
namespace {

std::string where(std::uint16_t index, std::uint8_t sub) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04Xh.%02X", index, sub);
  return buf;
}

std::string var_where(std::uint8_t var) {
  return std::string(1, static_cast<char>('a' + var)) + " (" + where(k_variable_index, var + 1) + ")";
}

std::string failure(od::AbortCode c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08X", od::to_u32(c));
  return std::string(buf) + " " + std::string(od::description(c));
}

// Two's-complement 32-bit view of a dictionary number (U32 above 0x7FFFFFFF reads negative).
std::int32_t as_i32(std::int64_t v) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(v)); }
std::int32_t wrap(std::uint32_t v) { return static_cast<std::int32_t>(v); }
std::uint32_t u(std::int32_t v) { return static_cast<std::uint32_t>(v); }

// SETOBJ's conversion to the entry's type (§9.3): truncation in two's complement.
std::int64_t to_entry_type(od::DataType t, std::int32_t v) {
  switch (t) {
    case od::DataType::boolean: return v != 0 ? 1 : 0;
    case od::DataType::integer8: return static_cast<std::int8_t>(static_cast<std::uint8_t>(u(v) & 0xFF));
    case od::DataType::unsigned8: return u(v) & 0xFF;
    case od::DataType::integer16: return static_cast<std::int16_t>(static_cast<std::uint16_t>(u(v) & 0xFFFF));
    case od::DataType::unsigned16: return u(v) & 0xFFFF;
    case od::DataType::unsigned32: return u(v);
    case od::DataType::integer32:
    case od::DataType::visible_string: return v;  // a string entry answers the type mismatch itself
  }
  return v;
}

}  // namespace

std::string_view to_string(RunState s) {
  switch (s) {
    case RunState::idle: return "idle";
    case RunState::running: return "running";
    case RunState::stopped: return "stopped";
    case RunState::finished: return "finished";
    case RunState::error: return "error";
  }
  return "?";
}

Interpreter::Interpreter(od::ObjectDictionary& od, VariableStorage& storage, Settings settings, EventSink sink)
    : od_(od), storage_(storage), settings_(std::move(settings)), sink_(std::move(sink)) {
  cycle_.reserve(k_history);
}

void Interpreter::set_statements_per_ms(std::uint32_t n) {
  settings_.statements_per_ms = n;
  forget_history();
}

std::optional<std::uint32_t> Interpreter::line() const {
  if (state_ == RunState::running && prog_) return prog_->code[m_.pc].line;
  if (state_ == RunState::error) return error_.line;
  return std::nullopt;
}

void Interpreter::emit(Event e) {
  if (!sink_) return;
  e.slot = slot_;
  e.time_ms = now_ms_;
  sink_(e);
}

void Interpreter::start(const Program& program, int slot) {
  if (running()) stop("restart");
  prog_ = &program;
  slot_ = slot;
  m_ = Machine{};
  loops_.assign(program.loops.size(), LoopState{});
  error_ = RunError{};
  state_ = RunState::running;
  waited_at_ = statements_;
  forget_history();
  emit(Event{.kind = EventKind::started});
  if (program.code.empty()) finish(RunState::finished, EventKind::finished, "end of program");  // not from load()
}

void Interpreter::stop(std::string_view why) {
  if (!running()) return;
  finish(RunState::stopped, EventKind::stopped, why);
}

void Interpreter::finish(RunState s, EventKind kind, std::string_view message) {
  state_ = s;
  forget_history();
  emit(Event{.kind = kind,
             .line = kind == EventKind::error ? error_.line : 0,
             .code = error_.code,
             .message = std::string(message)});
}

void Interpreter::fail(std::uint32_t line, std::string message, od::AbortCode code) {
  if (!running()) return;
  error_ = RunError{line, std::move(message), code};
  finish(RunState::error, EventKind::error, error_.message);
}

// ---- time

void Interpreter::step(std::uint64_t now_ms) {
  const std::uint64_t elapsed = have_time_ && now_ms > now_ms_ ? now_ms - now_ms_ : 0;
  now_ms_ = now_ms;
  have_time_ = true;
  if (!running()) return;
  const std::uint64_t gen0 = od_.generation();
  if (gen0 != last_end_generation_) forget_history();
  const Machine at_start = m_;
  impure_ = false;
  if (elapsed > 0) advance_timers(elapsed);
  if (running()) run(std::max<std::uint32_t>(settings_.statements_per_ms, 1));
  const std::uint64_t gen1 = od_.generation();
  last_end_generation_ = gen1;
  if (running() && settings_.idle_detection && !impure_ && gen1 == gen0) {
    remember(at_start);
  } else {
    forget_history();
  }
}

std::uint64_t Interpreter::quiet_steps() const {
  if (!running()) return k_never;
  return cycle_len_ > 0 && od_.generation() == last_end_generation_ ? k_never : 0;
}

void Interpreter::skip(std::uint64_t n) {
  now_ms_ += n;
  // a skip the contract does not allow (something changed since the last step) moves time only
  if (!running() || cycle_len_ == 0 || n == 0 || od_.generation() != last_end_generation_) return;
  statements_ += n * std::max<std::uint32_t>(settings_.statements_per_ms, 1);
  waited_at_ = statements_;  // a polling cycle that provably repeats: the program waits
  const std::size_t k = static_cast<std::size_t>(n % cycle_len_);
  std::rotate(cycle_.begin(), cycle_.begin() + static_cast<std::ptrdiff_t>(k), cycle_.end());
  m_ = cycle_[0];
  // The history must stay one contiguous run of steps ending just before the current state.
  for (std::size_t i = 0; i < cycle_len_; ++i) history_[i] = cycle_[i];
  hist_head_ = 0;
  hist_count_ = cycle_len_;
}

void Interpreter::forget_history() {
  hist_count_ = 0;
  hist_head_ = 0;
  cycle_len_ = 0;
  cycle_.clear();
}

void Interpreter::remember(const Machine& at_start) {
  if (hist_count_ == k_history) {
    hist_head_ = (hist_head_ + 1) % k_history;
    --hist_count_;
  }
  history_[(hist_head_ + hist_count_) % k_history] = at_start;
  ++hist_count_;
  // the newest match gives the shortest cycle
  for (std::size_t back = 0; back < hist_count_; ++back) {
    const std::size_t j = hist_count_ - 1 - back;
    if (!(history_[(hist_head_ + j) % k_history] == m_)) continue;
    cycle_.clear();
    for (std::size_t i = j; i < hist_count_; ++i) cycle_.push_back(history_[(hist_head_ + i) % k_history]);
    cycle_len_ = cycle_.size();
    return;
  }
  cycle_len_ = 0;
  cycle_.clear();
}

void Interpreter::advance_timers(std::uint64_t elapsed) {
  const std::uint32_t line = prog_->code[m_.pc].line;
  if (m_.tim_running) {
    std::int32_t v = 0;
    if (!read_var(static_cast<std::uint8_t>(m_.tim_var), v, line)) return;
    if (v > 0) {
      const std::int32_t next = elapsed >= static_cast<std::uint64_t>(v) ? 0 : v - static_cast<std::int32_t>(elapsed);
      if (!write_var(static_cast<std::uint8_t>(m_.tim_var), next, line)) return;
    }
  }
  if (m_.cyc_running) {
    std::int32_t v = 0;
    if (!read_var(static_cast<std::uint8_t>(m_.cyc_var), v, line)) return;
    if (!write_var(static_cast<std::uint8_t>(m_.cyc_var), wrap(u(v) + static_cast<std::uint32_t>(elapsed)), line)) {
      return;
    }
  }
}

// ---- statements

void Interpreter::run(std::uint32_t budget) {
  const auto& code = prog_->code;
  // Free instructions only jump forward or directly follow the statement that guards them; this
  // bound is a second line of defence, never reached by a program the loader accepted.
  std::size_t free_left = (code.size() + 1) * (static_cast<std::size_t>(budget) + 1);
  while (running()) {
    const Instr& in = code[m_.pc];
    if (in.cost != 0) {
      if (budget == 0) return;
      if (m_.ev_enabled && check_event()) continue;
      --budget;
      ++statements_;
    } else if (free_left-- == 0) {
      return;
    }
    execute(in);
  }
}

bool Interpreter::check_event() {
  waited_at_ = statements_;  // a registered handler: the program waits for an event
  const std::uint32_t line = prog_->code[m_.pc].line;
  std::int32_t status = 0;
  if (!read_object(k_status_index, k_status_sub, status, line)) return true;
  const std::uint32_t now = u(status) & m_.ev_mask;
  const bool edge = m_.ev_last == 0 && now != 0;
  m_.ev_last = now;
  if (m_.event_frame >= 0) {  // events do not nest: the edge is handled after RET_EVT
    if (edge) m_.ev_pending = true;
    return false;
  }
  if (!edge && !m_.ev_pending) return false;
  m_.ev_pending = false;
  if (m_.depth >= k_max_gosub_depth) {
    fail(line, "the event handler call exceeds the GOSUB depth of " + std::to_string(k_max_gosub_depth));
    return true;
  }
  m_.stack[m_.depth] = Frame{m_.pc, true};
  m_.event_frame = static_cast<std::int8_t>(m_.depth);
  ++m_.depth;
  if (m_.ev_var >= 0 && !write_var(static_cast<std::uint8_t>(m_.ev_var), status, line)) return true;
  m_.pc = m_.ev_handler;
  return true;
}

void Interpreter::execute(const Instr& in) {
  std::int32_t v = 0;
  switch (in.op) {
    case Op::assign:
      if (eval(in.a, v, in.line) && write_var(in.var, v, in.line)) ++m_.pc;
      return;
    case Op::setobj:
      if (eval(in.a, v, in.line)) setobj(in, v);
      return;
    case Op::jump: m_.pc = in.target; return;
    case Op::jump_if_false:
      if (eval(in.a, v, in.line)) m_.pc = v != 0 ? m_.pc + 1 : in.target;
      return;
    case Op::gosub:
      if (m_.depth >= k_max_gosub_depth) {
        return fail(in.line, "GOSUB nested deeper than " + std::to_string(k_max_gosub_depth) + " levels");
      }
      m_.stack[m_.depth++] = Frame{m_.pc + 1, false};
      m_.pc = in.target;
      return;
    case Op::ret:
      if (m_.depth == 0) return fail(in.line, "RETURN without GOSUB");
      if (m_.stack[m_.depth - 1].event) {
        return fail(in.line, "RETURN in an event handler without GOSUB (a handler ends with RET_EVT)");
      }
      m_.pc = m_.stack[--m_.depth].return_pc;
      m_.stack[m_.depth] = Frame{};
      return;
    case Op::for_init: {
      impure_ = true;
      const Loop& l = prog_->loops[in.slot];
      std::int32_t from = 0, to = 0, step = 1;
      if (!eval(l.from, from, in.line) || !eval(l.to, to, in.line)) return;
      if (l.has_step && !eval(l.step, step, in.line)) return;
      if (!write_var(l.var, from, in.line)) return;
      const bool enter = step >= 0 ? from <= to : from >= to;
      loops_[in.slot] = LoopState{enter, to, step};
      m_.pc = enter ? m_.pc + 1 : in.target;
      return;
    }
    case Op::next: {
      impure_ = true;
      LoopState& l = loops_[in.slot];
      if (!l.active) return fail(in.line, "NEXT of a FOR loop that is not running (entered by GOTO?)");
      if (!read_var(in.var, v, in.line)) return;
      // 64-bit sum: a loop up to 2147483647 ends instead of wrapping around forever
      const std::int64_t next = static_cast<std::int64_t>(v) + l.step;
      const bool again = l.step >= 0 ? next <= l.to : next >= l.to;
      if (!write_var(in.var, wrap(static_cast<std::uint32_t>(next)), in.line)) return;
      if (again) {
        m_.pc = in.target;
      } else {
        l.active = false;
        ++m_.pc;
      }
      return;
    }
    case Op::en_evt: {
      std::int32_t status = 0;
      if (!eval(in.a, v, in.line) || !read_object(k_status_index, k_status_sub, status, in.line)) return;
      m_.ev_enabled = true;
      m_.ev_pending = false;
      m_.ev_mask = u(v);
      m_.ev_handler = in.target;
      m_.ev_last = u(status) & m_.ev_mask;  // a condition already present is not an edge
      ++m_.pc;
      return;
    }
    case Op::di_evt:
      m_.ev_enabled = false;
      m_.ev_pending = false;
      ++m_.pc;
      return;
    case Op::def_evt_var:
      m_.ev_var = static_cast<std::int8_t>(in.var);
      ++m_.pc;
      return;
    case Op::ret_evt: {
      if (m_.event_frame < 0) return fail(in.line, "RET_EVT outside an event handler");
      const auto f = static_cast<std::uint8_t>(m_.event_frame);
      m_.pc = m_.stack[f].return_pc;
      for (std::uint8_t i = f; i < m_.depth; ++i) m_.stack[i] = Frame{};
      m_.depth = f;
      m_.event_frame = -1;
      return;
    }
    case Op::def_tim_var:
      m_.tim_var = static_cast<std::int8_t>(in.var);
      m_.tim_running = false;
      ++m_.pc;
      return;
    case Op::start_tim:
      if (m_.tim_var < 0) return fail(in.line, "START_TIM before DEF_TIM_VAR");
      if (!eval(in.a, v, in.line) || !write_var(static_cast<std::uint8_t>(m_.tim_var), std::max(v, 0), in.line)) {
        return;
      }
      m_.tim_running = true;
      ++m_.pc;
      return;
    case Op::def_cyc_var:
      m_.cyc_var = static_cast<std::int8_t>(in.var);
      m_.cyc_running = false;
      ++m_.pc;
      return;
    case Op::start_cyc:
      if (m_.cyc_var < 0) return fail(in.line, "START_CYC before DEF_CYC_VAR");
      if (!write_var(static_cast<std::uint8_t>(m_.cyc_var), 0, in.line)) return;
      m_.cyc_running = true;
      ++m_.pc;
      return;
    case Op::stop_cyc:
      if (m_.cyc_var < 0) return fail(in.line, "STOP_CYC before DEF_CYC_VAR");
      m_.cyc_running = false;
      ++m_.pc;
      return;
    case Op::save: save(in); return;
    case Op::load:
      impure_ = true;
      for (std::uint32_t i = 0; i < in.count; ++i) {
        const std::uint8_t var = prog_->lists[in.slot + i];
        if (!write_var(var, storage_.load(var).value_or(0), in.line)) return;
      }
      ++m_.pc;
      return;
    case Op::end: finish(RunState::finished, EventKind::finished, "end of program"); return;
  }
}

void Interpreter::setobj(const Instr& in, std::int32_t value) {
  impure_ = true;
  const od::EntryInfo* info = od_.info(in.index, in.sub);
  const std::int64_t converted = info ? to_entry_type(info->type, value) : value;
  od::AbortCode code = od_.write(in.index, in.sub, od::Value{converted}, od::Origin::script);
  if (code == od::AbortCode::pending) code = od::AbortCode::none;  // Store/Restore completes later
  emit(Event{
      .kind = EventKind::setobj, .line = in.line, .index = in.index, .sub = in.sub, .value = converted, .code = code});
  if (code != od::AbortCode::none) {
    return fail(in.line, "SETOBJ " + where(in.index, in.sub) + " = " + std::to_string(converted) + ": " + failure(code),
                code);
  }
  ++m_.pc;
}

void Interpreter::save(const Instr& in) {
  impure_ = true;
  std::vector<SavedVariable> saved;
  saved.reserve(in.count);
  for (std::uint32_t i = 0; i < in.count; ++i) {
    const std::uint8_t var = prog_->lists[in.slot + i];
    std::int32_t v = 0;
    if (!read_var(var, v, in.line)) return;
    saved.push_back(SavedVariable{var, v});
  }
  storage_.save(saved);
  ++save_count_;
  emit(Event{.kind = EventKind::save, .line = in.line, .saved = std::move(saved), .save_count = save_count_});
  ++m_.pc;
}

// ---- values

bool Interpreter::read_object(std::uint16_t index, std::uint8_t sub, std::int32_t& out, std::uint32_t line) {
  const auto r = od_.read_number(index, sub);
  if (!r) {
    fail(line, "GETOBJ " + where(index, sub) + ": " + failure(r.error()), r.error());
    return false;
  }
  if (settings_.time_dependent && settings_.time_dependent(index, sub)) impure_ = true;
  out = as_i32(*r);
  return true;
}

bool Interpreter::read_var(std::uint8_t var, std::int32_t& out, std::uint32_t line) {
  const auto r = od_.read_number(k_variable_index, static_cast<std::uint8_t>(var + 1));
  if (!r) {
    fail(line, "reading variable " + var_where(var) + ": " + failure(r.error()), r.error());
    return false;
  }
  out = as_i32(*r);
  return true;
}

bool Interpreter::write_var(std::uint8_t var, std::int32_t value, std::uint32_t line) {
  const od::AbortCode c = od_.write(k_variable_index, static_cast<std::uint8_t>(var + 1),
                                    od::Value{std::int64_t{value}}, od::Origin::script);
  if (c == od::AbortCode::none) return true;
  fail(line, "writing variable " + var_where(var) + " = " + std::to_string(value) + ": " + failure(c), c);
  return false;
}

bool Interpreter::eval(const ExprRange& r, std::int32_t& out, std::uint32_t line) {
  std::array<std::int32_t, k_max_expression_stack + 1> st;
  std::size_t sp = 0;
  const XOp* ops = prog_->expr.data();
  for (std::uint32_t i = r.begin; i < r.end; ++i) {
    const XOp& x = ops[i];
    switch (x.op) {
      case X::constant: st[sp++] = x.value; continue;
      case X::variable:
        if (x.value == m_.tim_var || x.value == m_.cyc_var) waited_at_ = statements_;  // a timer wait
        if (!read_var(static_cast<std::uint8_t>(x.value), st[sp], line)) return false;
        ++sp;
        continue;
      case X::getobj:
        waited_at_ = statements_;  // polls the drive
        if (!read_object(x.index, x.sub, st[sp], line)) return false;
        ++sp;
        continue;
      case X::neg: st[sp - 1] = wrap(0U - u(st[sp - 1])); continue;
      case X::bnot: st[sp - 1] = ~st[sp - 1]; continue;
      case X::lnot: st[sp - 1] = st[sp - 1] == 0 ? 1 : 0; continue;
      default: break;
    }
    const std::int32_t b = st[--sp];
    std::int32_t& a = st[sp - 1];
    switch (x.op) {
      case X::mul: a = wrap(u(a) * u(b)); break;
      case X::div:
      case X::mod:
        if (b == 0) {
          fail(line, x.op == X::div ? "division by zero" : "remainder of a division by zero");
          return false;
        }
        if (b == -1) {  // INT32_MIN / -1 overflows in C++; in two's complement it wraps
          a = x.op == X::div ? wrap(0U - u(a)) : 0;
        } else {
          a = x.op == X::div ? a / b : a % b;
        }
        break;
      case X::add: a = wrap(u(a) + u(b)); break;
      case X::sub: a = wrap(u(a) - u(b)); break;
      case X::band: a = a & b; break;
      case X::bor: a = a | b; break;
      case X::eq: a = a == b; break;
      case X::ne: a = a != b; break;
      case X::lt: a = a < b; break;
      case X::gt: a = a > b; break;
      case X::le: a = a <= b; break;
      case X::ge: a = a >= b; break;
      case X::land: a = (a != 0 && b != 0) ? 1 : 0; break;
      case X::lor: a = (a != 0 || b != 0) ? 1 : 0; break;
      default: break;
    }
  }
  out = sp > 0 ? st[sp - 1] : 0;
  return true;
}

}  // namespace mcemu::basic
