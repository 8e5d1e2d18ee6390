#include "device/faults.hpp"

#include <algorithm>
#include <cmath>

#include "device/json_fields.hpp"
#include "drive/drive_core.hpp"
#include "drive/faults.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/objects.hpp"

namespace mcemu::device {

using nlohmann::json;

namespace {

// The ambient temperature the drive core starts with (drive-core.md §10.7).
constexpr double k_default_ambient_c = 25.0;
constexpr std::uint64_t k_max_count = 0xFFFFFFFFULL;
constexpr std::uint64_t k_max_duration_ms = 1ULL << 40;  // ~35 years of drive time
constexpr std::uint64_t k_max_delay_ms = 600000;
constexpr std::size_t k_max_raw_text = 1024;
constexpr std::uint32_t k_error_bits = 0x3FFF;  // 1002h bits 0–13 (drive-core.md §11.1)

Refusal bad(const std::string& message) { return Refusal{Refusal::Kind::syntax, message}; }

// A finite JSON number in [lo, hi].
std::optional<double> number_in(const json& body, const char* key, double lo, double hi) {
  const auto it = body.find(key);
  if (it == body.end() || !it->is_number()) return std::nullopt;
  const double v = it->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) return std::nullopt;
  return v;
}

}  // namespace

struct FaultInjections::Parsed {
  const KindRow* row = nullptr;
  std::function<void()> apply;  // the effect, run once the injection is listed
  std::function<void()> undo;
  std::optional<int> cause_bit;
  std::optional<TransportFault> transport;
  bool one_shot = false;          // acts in apply() and is not listed
  bool expire_next_step = false;  // drive.emcy of a cause: present for one step
};

const std::vector<FaultInjections::KindRow>& FaultInjections::kinds() {
  static const std::vector<KindRow> rows{
      {"drive.inject", {"cause"}, &FaultInjections::parse_inject},
      {"drive.emcy", {"code"}, &FaultInjections::parse_emcy},
      {"drive.supply", {"volts"}, &FaultInjections::parse_supply},
      {"drive.ambient", {"celsius"}, &FaultInjections::parse_ambient},
      {"drive.load", {"value"}, &FaultInjections::parse_load},
      {"drive.obstacle", {"positionInc", "side"}, &FaultInjections::parse_obstacle},
      {"refgo.noReply", {}, &FaultInjections::parse_transport},
      {"refgo.delay", {"ms"}, &FaultInjections::parse_transport},
      {"refgo.disconnect", {}, &FaultInjections::parse_transport},
      {"udp.drop", {}, &FaultInjections::parse_transport},
      {"http.error", {"status", "path"}, &FaultInjections::parse_transport},
      {"script.kill", {}, &FaultInjections::parse_script_kill},
      {"slcan.dropTx", {"cobId"}, &FaultInjections::parse_transport},
      {"slcan.delayTx", {"ms"}, &FaultInjections::parse_transport},
      {"slcan.sdoAbort", {"index", "sub", "code", "phase"}, &FaultInjections::parse_transport},
      {"slcan.sdoNoReply", {"index"}, &FaultInjections::parse_transport},
      {"slcan.heartbeatStop", {}, &FaultInjections::parse_transport},
      {"slcan.rawTx", {"text"}, &FaultInjections::parse_transport},
      {"slcan.bel", {}, &FaultInjections::parse_transport},
      {"slcan.disconnect", {}, &FaultInjections::parse_transport},
  };
  return rows;
}

FaultInjections::FaultInjections(od::ObjectDictionary& od, core::DriveCore& core) : od_(od), core_(core) {
  if (const auto v = od_.read_number(od::k_mfr_status, 0)) last_1002_ = static_cast<std::uint32_t>(*v);
  od_.on_change({{od::k_mfr_status, 0}}, [this, alive = alive_.watch()](const od::EntryInfo&, const od::Value& value) {
    if (!alive) return;
    if (const auto* n = std::get_if<std::int64_t>(&value)) on_fault_bits(static_cast<std::uint32_t>(*n));
  });
  transport_.set_removed_listener([this](const std::string& id, std::string_view reason) {
    const auto it = std::find_if(active_.begin(), active_.end(), [&](const Injection& i) { return i.id == id; });
    if (it == active_.end()) return;
    active_.erase(it);
    report("fault " + id + " removed (" + std::string(reason) + ")",
           "fault injection " + id + " removed (" + std::string(reason) + ")");
  });
}

FaultInjections::~FaultInjections() { alive_.end(); }

void FaultInjections::report(const std::string& trace_text, const std::string& note_text) {
  if (journal_) journal_(trace_text, note_text);
}

Outcome<nlohmann::json> FaultInjections::create(const std::string& text) {
  const json body = json::parse(text, nullptr, false);
  if (body.is_discarded() || !body.is_object()) return bad("expected a JSON object {\"kind\": \"…\", …}");
  const auto kind_it = body.find("kind");
  if (kind_it == body.end() || !kind_it->is_string()) return bad("\"kind\" is missing or not a string");
  const std::string kind = kind_it->get<std::string>();
  const auto& rows = kinds();
  const auto row = std::find_if(rows.begin(), rows.end(), [&](const KindRow& r) { return kind == r.name; });
  if (row == rows.end()) return bad("\"kind\": unknown fault kind \"" + kind + "\"");
  if (available_ && !available_(kind)) {
    return Refusal{Refusal::Kind::unavailable, "fault kind " + kind + " does not exist on this drive"};
  }
  for (const auto& item : body.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture those
    if (key == "kind" || key == "count" || key == "durationMs") continue;
    if (std::none_of(row->fields.begin(), row->fields.end(), [&](const char* f) { return key == f; })) {
      return bad("\"" + key + "\": not a field of kind " + kind);
    }
  }
  std::optional<std::uint64_t> count;
  if (const auto it = body.find("count"); it != body.end()) {
    count = json_uint(*it, 1, k_max_count);
    if (!count) return bad("\"count\" must be an integer 1 … 4294967295");
  }
  std::optional<std::uint64_t> expires;
  if (const auto it = body.find("durationMs"); it != body.end()) {
    const auto d = json_uint(*it, 1, k_max_duration_ms);
    if (!d) return bad("\"durationMs\" must be a positive integer (drive time in ms)");
    expires = core_.time_ms() + *d;
  }

  Parsed p;
  p.row = &*row;
  if (auto error = (this->*row->parse)(body, p)) return *std::move(error);

  const std::string id = "f" + std::to_string(next_id_++);
  json description = body;
  description["id"] = id;
  report("fault " + id + " added: " + dump_json(body), "fault injection " + id + " " + kind + " added");

  if (p.one_shot) {
    p.apply();
    report("fault " + id + " removed (done)", "fault injection " + id + " done");
    return description;
  }
  Injection inj;
  inj.id = id;
  inj.kind = kind;
  inj.description = description;
  inj.expires = p.expire_next_step ? std::optional<std::uint64_t>(core_.time_ms() + 1) : expires;
  if (p.transport) {
    inj.transport = true;
    p.transport->id = id;
    p.transport->remaining = count;
    // "the next matching SDO transfer" (slcan-canopen.md §11.3): one, unless count says more.
    if (!count && p.transport->kind == TransportKind::slcan_sdo_abort) p.transport->remaining = 1;
    active_.push_back(std::move(inj));
    transport_.add(std::move(*p.transport));  // may remove a one-shot at once (listener)
    return description;
  }
  inj.remaining = count;
  inj.cause_bit = p.cause_bit;
  inj.undo = std::move(p.undo);
  active_.push_back(std::move(inj));
  // After listing, so that a fault raised inside the call (event causes) is counted.
  if (p.apply) p.apply();
  return description;
}

// ---- drive kinds ------------------------------------------------------------------------------

std::optional<Refusal> FaultInjections::parse_inject(const json& b, Parsed& out) {
  const auto it = b.find("cause");
  const auto cause =
      it != b.end() && it->is_string() ? core::fault_cause_from_string(it->get<std::string>()) : std::nullopt;
  if (!cause) return bad("\"cause\": one of the API names of drive-core.md §11.1 (under_voltage, stroke, …)");
  out.cause_bit = core::fault_info(*cause).bit;
  out.apply = [this, c = *cause] { core_.inject(c); };
  out.undo = [this, c = *cause] { core_.clear(c); };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_emcy(const json& b, Parsed& out) {
  const auto it = b.find("code");
  const auto code = it != b.end() ? json_hex_or_number(*it, 0xFFFF) : std::nullopt;
  if (!code) return bad("\"code\": an EMCY code, e.g. \"7121h\"");
  const auto table = core::fault_table();
  const auto f = std::find_if(table.begin(), table.end(),
                              [&](const core::FaultInfo& i) { return i.code == *code && i.code != 0; });
  if (f == table.end()) {
    // Not a cause of §11.1: one EMCY message only, like mcdrive.SendEmcyMsg(0, 0, code) (web.md §9).
    out.one_shot = true;
    out.apply = [this, c = static_cast<std::uint16_t>(*code)] { core_.send_script_emcy(0, 0, c); };
    return std::nullopt;
  }
  // The cause is present for one drive step, so that the step's fault check sees it; the fault
  // itself stays until a fault reset (drive-core.md §11.9).
  out.expire_next_step = true;
  out.apply = [this, c = f->cause] { core_.inject(c); };
  out.undo = [this, c = f->cause] { core_.clear(c); };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_supply(const json& b, Parsed& out) {
  const auto v = number_in(b, "volts", 0, 1000);
  if (!v) return bad("\"volts\": a number 0 … 1000");
  out.apply = [this, v = *v] { core_.set_supply_voltage(v); };
  out.undo = [this] { core_.set_supply_voltage(core_.plant_params().supply_nominal_v); };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_ambient(const json& b, Parsed& out) {
  const auto v = number_in(b, "celsius", -100, 500);
  if (!v) return bad("\"celsius\": a number -100 … 500");
  out.apply = [this, v = *v] { core_.set_ambient_temperature(v); };
  out.undo = [this] { core_.set_ambient_temperature(k_default_ambient_c); };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_load(const json& b, Parsed& out) {
  const auto v = number_in(b, "value", -1e6, 1e6);
  if (!v) return bad("\"value\": the load in N·m (rotary) or N (linear), -1e6 … 1e6");
  out.apply = [this, v = *v] { core_.set_external_load(v); };
  out.undo = [this] { core_.set_external_load(0); };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_obstacle(const json& b, Parsed& out) {
  const auto pos = b.find("positionInc");
  if (pos == b.end() || !pos->is_number_integer() ||
      (pos->is_number_unsigned() && pos->get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX))) {
    return bad("\"positionInc\": an integer (raw position in increments)");
  }
  const auto side = b.find("side");
  if (side == b.end() || !side->is_number_integer() || (*side != 1 && *side != -1)) {
    return bad("\"side\": +1 (blocks the positive direction) or -1");
  }
  const core::Obstacle o{pos->get<std::int64_t>(), side->get<int>()};
  auto id = std::make_shared<std::optional<core::ObstacleId>>();
  out.apply = [this, o, id] { *id = core_.add_obstacle(o); };
  out.undo = [this, id] {
    if (*id) core_.remove_obstacle(**id);
  };
  return std::nullopt;
}

std::optional<Refusal> FaultInjections::parse_script_kill(const json&, Parsed& out) {
  if (!kill_script_) return Refusal{Refusal::Kind::unavailable, "script engine not available in this version"};
  if (script_running_ && !script_running_()) {
    return Refusal{Refusal::Kind::conflict, "no script engine process to kill: the script is not running (OFF)"};
  }
  out.one_shot = true;
  out.apply = kill_script_;
  return std::nullopt;
}

// ---- transport kinds --------------------------------------------------------------------------

std::optional<Refusal> FaultInjections::parse_transport(const json& b, Parsed& out) {
  const std::string_view kind = out.row->name;
  TransportFault f;
  const auto ms = [&]() -> std::optional<Refusal> {
    const auto it = b.find("ms");
    const auto v = it != b.end() ? json_uint(*it, 1, k_max_delay_ms) : std::nullopt;
    if (!v) return bad("\"ms\": an integer 1 … 600000 (wall time)");
    f.ms = static_cast<std::uint32_t>(*v);
    return std::nullopt;
  };
  const auto optional_index = [&]() -> std::optional<Refusal> {
    const auto it = b.find("index");
    if (it == b.end()) return std::nullopt;
    const auto v = json_hex_or_number(*it, 0xFFFF);
    if (!v) return bad("\"index\": an object index, e.g. \"6041h\"");
    f.index = static_cast<std::uint16_t>(*v);
    return std::nullopt;
  };
  if (kind == "refgo.noReply") {
    f.kind = TransportKind::refgo_no_reply;
  } else if (kind == "refgo.delay") {
    f.kind = TransportKind::refgo_delay;
    if (auto e = ms()) return e;
  } else if (kind == "refgo.disconnect") {
    f.kind = TransportKind::refgo_disconnect;
  } else if (kind == "udp.drop") {
    f.kind = TransportKind::udp_drop;
  } else if (kind == "http.error") {
    f.kind = TransportKind::http_error;
    const auto it = b.find("status");
    const auto status = it != b.end() ? json_uint(*it, 400, 599) : std::nullopt;
    if (!status) return bad("\"status\": an HTTP error status 400 … 599");
    f.status = static_cast<int>(*status);
    if (const auto p = b.find("path"); p != b.end()) {
      if (!p->is_string() || p->get_ref<const std::string&>().empty() || p->get_ref<const std::string&>()[0] != '/' ||
          p->get_ref<const std::string&>().rfind("/api/", 0) == 0) {
        return bad("\"path\": a page path prefix starting with \"/\" (not /api/)");
      }
      f.path = p->get<std::string>();
    }
  } else if (kind == "slcan.dropTx") {
    f.kind = TransportKind::slcan_drop_tx;
    if (const auto it = b.find("cobId"); it != b.end()) {
      const auto v = json_hex_or_number(*it, 0x1FFFFFFF);
      if (!v) return bad("\"cobId\": a CAN identifier 0 … 1FFFFFFFh");
      f.cob_id = *v;
    }
  } else if (kind == "slcan.delayTx") {
    f.kind = TransportKind::slcan_delay_tx;
    if (auto e = ms()) return e;
  } else if (kind == "slcan.sdoAbort") {
    f.kind = TransportKind::slcan_sdo_abort;
    if (!b.contains("index")) return bad("\"index\": an object index, e.g. \"6041h\"");
    if (auto e = optional_index()) return e;
    const auto sub = b.find("sub");
    const auto s = sub != b.end() ? json_hex_or_number(*sub, 0xFF) : std::nullopt;
    if (!s) return bad("\"sub\": a sub-index 0 … FFh");
    f.sub = static_cast<std::uint8_t>(*s);
    const auto code = b.find("code");
    const auto c = code != b.end() ? json_hex_or_number(*code, 0xFFFFFFFF) : std::nullopt;
    if (!c || *c == 0) return bad("\"code\": an SDO abort code, e.g. \"06090011h\"");
    f.abort_code = *c;
    if (const auto ph = b.find("phase"); ph != b.end()) {
      if (*ph == "initiate") {
        f.phase = SdoPhase::initiate;
      } else if (*ph == "segment") {
        f.phase = SdoPhase::segment;
      } else if (*ph == "end") {
        f.phase = SdoPhase::end;
      } else {
        return bad("\"phase\": initiate, segment or end");
      }
    }
  } else if (kind == "slcan.sdoNoReply") {
    f.kind = TransportKind::slcan_sdo_no_reply;
    if (auto e = optional_index()) return e;
  } else if (kind == "slcan.heartbeatStop") {
    f.kind = TransportKind::slcan_heartbeat_stop;
  } else if (kind == "slcan.rawTx") {
    f.kind = TransportKind::slcan_raw_tx;
    const auto it = b.find("text");
    const bool ok = it != b.end() && it->is_string() && !it->get_ref<const std::string&>().empty() &&
                    it->get_ref<const std::string&>().size() <= k_max_raw_text &&
                    std::all_of(it->get_ref<const std::string&>().begin(), it->get_ref<const std::string&>().end(),
                                [](char c) { return c == '\r' || (c >= 0x20 && c <= 0x7E); });
    if (!ok) return bad("\"text\": 1 … 1024 characters of printable ASCII (\\r allowed)");
    f.text = it->get<std::string>();
  } else if (kind == "slcan.bel") {
    f.kind = TransportKind::slcan_bel;
  } else {
    f.kind = TransportKind::slcan_disconnect;
  }
  out.transport = std::move(f);
  return std::nullopt;
}

// ---- listing and removal ----------------------------------------------------------------------

nlohmann::json FaultInjections::list() const {
  json all = json::array();
  for (const auto& i : active_) {
    json d = i.description;
    std::optional<std::uint64_t> remaining = i.remaining;
    if (i.transport) {
      const auto& t = transport_.active();
      const auto it = std::find_if(t.begin(), t.end(), [&](const TransportFault& f) { return f.id == i.id; });
      if (it != t.end()) remaining = it->remaining;
    }
    if (remaining) d["remaining"] = *remaining;
    if (i.expires) d["expiresAtMs"] = *i.expires;
    all.push_back(std::move(d));
  }
  return json{{"faults", all}};
}

void FaultInjections::erase(const std::string& id, std::string_view reason, bool undo) {
  const auto it = std::find_if(active_.begin(), active_.end(), [&](const Injection& i) { return i.id == id; });
  if (it == active_.end()) return;
  Injection inj = std::move(*it);
  active_.erase(it);
  if (inj.transport) transport_.remove(id);
  if (undo && inj.undo) inj.undo();
  report("fault " + id + " removed (" + std::string(reason) + ")",
         "fault injection " + id + " removed (" + std::string(reason) + ")");
}

std::optional<Refusal> FaultInjections::remove(const std::string& id) {
  if (std::none_of(active_.begin(), active_.end(), [&](const Injection& i) { return i.id == id; })) {
    return Refusal{Refusal::Kind::not_found, "no active injection " + id};
  }
  erase(id, "api", true);
  return std::nullopt;
}

void FaultInjections::remove_all() {
  std::vector<std::string> ids;
  for (const auto& i : active_) ids.push_back(i.id);
  for (const auto& id : ids) erase(id, "all", true);
}

void FaultInjections::on_fault_bits(std::uint32_t value) {
  const std::uint32_t raised = value & ~last_1002_;
  last_1002_ = value;
  if (raised == 0) return;
  for (auto& i : active_) {
    if (i.transport || !i.remaining || i.used_up) continue;
    const bool counts = i.cause_bit ? ((raised >> *i.cause_bit) & 1U) != 0 : (raised & k_error_bits) != 0;
    if (!counts) continue;
    if (--*i.remaining == 0) i.used_up = true;  // removed after the step, not inside the core's write
  }
}

void FaultInjections::on_step() {
  const auto now = core_.time_ms();
  if (now < last_time_ms_) {
    // Drive time restarted at 0 (power on, NMT reset node): each duration keeps the time it had
    // left, counted from the restart.
    for (auto& i : active_) {
      if (i.expires) i.expires = *i.expires > last_time_ms_ ? *i.expires - last_time_ms_ : 0;
    }
  }
  last_time_ms_ = now;
  if (active_.empty()) return;  // the usual case, in every step of every drive
  std::vector<std::pair<std::string, const char*>> due;
  for (const auto& i : active_) {
    if (i.used_up) {
      due.emplace_back(i.id, "count");
    } else if (i.expires && *i.expires <= now) {
      due.emplace_back(i.id, "duration");
    }
  }
  for (const auto& [id, reason] : due) erase(id, reason, true);
}

std::optional<std::uint64_t> FaultInjections::next_expiry() const {
  std::optional<std::uint64_t> best;
  for (const auto& i : active_) {
    if (i.used_up) return core_.time_ms();  // removed by the next on_step()
    if (i.expires && (!best || *i.expires < *best)) best = i.expires;
  }
  return best;
}

}  // namespace mcemu::device
