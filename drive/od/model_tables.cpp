// Builds a preset's dictionary: the XDD transcription, the additions of object-dictionary.md §8.3,
// the classes of §2.6, the write limits of §5 and the factory values of §7 / models.md §3.
#include "drive/od/model_tables.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <stdexcept>
#include <string>

#include "drive/model/model_preset.hpp"
#include "drive/od/dictionary.hpp"
#include "drive/od/faulhaber_table.hpp"
#include "drive/od/tables/xdd_tables.hpp"
#include "drive/od/validators.hpp"

namespace mcemu::od {
namespace {

using model::Base;

constexpr std::int64_t k_factory_node_id = 50;

bool in(std::uint16_t index, std::uint16_t lo, std::uint16_t hi) { return index >= lo && index <= hi; }

// XDD default text → value ("0x3E8", "-2147483647", "$NODEID+0x600", "CANopen Slave").
Value parse_default(const tables::XddEntry& x) {
  const std::string_view text = x.xdd_default ? std::string_view(x.xdd_default) : std::string_view();
  if (is_string(x.type)) return Value{text == "0x0" ? std::string{} : std::string(text)};
  if (text.empty()) return Value{std::int64_t{0}};
  std::string_view t = text;
  std::int64_t add = 0;
  if (t.starts_with("$NODEID+")) {
    add = k_factory_node_id;
    t.remove_prefix(8);
  }
  int base = 10;
  if (t.starts_with("0x") || t.starts_with("0X")) {
    base = 16;
    t.remove_prefix(2);
  }
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v, base);
  if (ec != std::errc{} || end != t.data() + t.size()) {
    throw std::logic_error("XDD default \"" + std::string(text) + "\" is not a number");
  }
  return Value{v + add};
}

EntryInfo from_xdd(const tables::XddEntry& x) {
  EntryInfo e;
  e.index = x.index;
  e.sub = x.sub;
  e.object_code = x.object_code;
  e.type = x.type;
  e.access = x.access;
  e.pdo = x.pdo;
  e.name = x.name;
  e.object_name = x.object_name;
  e.factory = parse_default(x);
  return e;
}

EntryInfo extra(std::uint16_t index, std::uint8_t sub, std::uint8_t code, DataType type, Access access,
                std::string_view name, std::string_view object_name, Value factory) {
  EntryInfo e;
  e.index = index;
  e.sub = sub;
  e.object_code = code;
  e.type = type;
  e.access = access;
  e.name = name;
  e.object_name = object_name;
  e.factory = std::move(factory);
  e.from_xdd = false;
  return e;
}

Value num(std::int64_t v) { return Value{v}; }

void add_record_head(std::vector<EntryInfo>& out, std::uint16_t index, std::int64_t highest, std::string_view obj) {
  out.push_back(extra(index, 0, 9, DataType::unsigned8, Access::ro, "NrOfObjects", obj, num(highest)));
}

// "Python unsigned8 1" … "Python integer32 10": the names of the generated 340Bh–3410h entries,
// built once for the process (EntryInfo names are views).
std::string_view python_param_name(std::size_t type, std::uint8_t sub) {
  static const auto names = [] {
    constexpr std::array<const char*, 6> k_types = {"unsigned8", "integer8",   "unsigned16",
                                                    "integer16", "unsigned32", "integer32"};
    std::array<std::array<std::string, 10>, 6> n;
    for (std::size_t t = 0; t < 6; ++t) {
      for (std::size_t s = 0; s < 10; ++s) n[t][s] = std::string("Python ") + k_types[t] + " " + std::to_string(s + 1);
    }
    return n;
  }();
  return names[type][sub - 1];
}

constexpr std::array<const char*, 4> k_ip_names = {"ip address 1", "ip address 2", "ip address 3", "ip address 4"};
constexpr std::array<const char*, 4> k_mask_names = {"mask 1", "mask 2", "mask 3", "mask 4"};

// The additions go to `out`; `xdd` is the model's XDD table, sorted by (index, sub).
void add_extras(std::vector<EntryInfo>& out, std::span<const tables::XddEntry> xdd, const model::ModelPreset& p) {
  const auto has = [&](std::uint16_t i) {
    const auto it = std::lower_bound(xdd.begin(), xdd.end(), i,
                                     [](const tables::XddEntry& x, std::uint16_t index) { return x.index < index; });
    return (it != xdd.end() && it->index == i) ||
           std::any_of(out.begin(), out.end(), [&](const EntryInfo& e) { return e.index == i; });
  };
  const auto has_entry = [&](std::uint16_t i, std::uint8_t s) {
    return std::any_of(xdd.begin(), xdd.end(), [&](const tables::XddEntry& x) { return x.index == i && x.sub == s; }) ||
           std::any_of(out.begin(), out.end(), [&](const EntryInfo& e) { return e.index == i && e.sub == s; });
  };
  // 1400h RPDO1 communication (missing from the MC349 XDD).
  if (!has(0x1400)) {
    const std::string_view o = "1. receive PDO parameter";
    out.push_back(extra(0x1400, 0, 9, DataType::unsigned8, Access::ro, "largest subindex supported", o, num(3)));
    out.push_back(
        extra(0x1400, 1, 9, DataType::unsigned32, Access::rw, "COB-Id used", o, num(0x200 + k_factory_node_id)));
    out.push_back(extra(0x1400, 2, 9, DataType::unsigned8, Access::rw, "transmission type", o, num(0xFF)));
    out.push_back(extra(0x1400, 3, 9, DataType::unsigned16, Access::rw, "inhibit time", o, num(0)));
  }
  // 340Bh–3410h Python user parameters (missing from the MC6xx XDD).
  struct Py {
    std::uint16_t index;
    DataType type;
    const char* name;
  };
  std::size_t type_no = 0;
  for (const Py& py :
       {Py{0x340B, DataType::unsigned8, "Python unsigned8"}, Py{0x340C, DataType::integer8, "Python integer8"},
        Py{0x340D, DataType::unsigned16, "Python unsigned16"}, Py{0x340E, DataType::integer16, "Python integer16"},
        Py{0x340F, DataType::unsigned32, "Python unsigned32"}, Py{0x3410, DataType::integer32, "Python integer32"}}) {
    const std::size_t t = type_no++;
    if (has(py.index)) continue;
    add_record_head(out, py.index, 10, py.name);
    for (std::uint8_t s = 1; s <= 10; ++s) {
      out.push_back(extra(py.index, s, 9, py.type, Access::rw, python_param_name(t, s), py.name, num(0)));
    }
  }
  // 3500h Python (missing from MC6xx) and .03–.06 on every model.
  if (!has(0x3500)) {
    add_record_head(out, 0x3500, 6, "Python");
    out.push_back(
        extra(0x3500, 1, 9, DataType::visible_string, Access::ro, "Script name", "Python", Value{std::string{}}));
    out.push_back(extra(0x3500, 2, 9, DataType::unsigned8, Access::rw, "Script control", "Python", num(0)));
  }
  out.push_back(extra(0x3500, 3, 9, DataType::unsigned8, Access::ro, "Python Current Line", "Python", num(0)));
  out.push_back(extra(0x3500, 4, 9, DataType::unsigned8, Access::rw, "Python Autostart", "Python", num(0)));
  out.push_back(extra(0x3500, 5, 9, DataType::unsigned32, Access::ro, "Python Source Len", "Python", num(13)));
  out.push_back(
      extra(0x3500, 6, 9, DataType::unsigned32, Access::ro, "Python Source CRC32", "Python", num(0x23883CEF)));
  // 3510h IO simulation, 5006h NVM statistics: every model.
  add_record_head(out, 0x3510, 2, "MovingCap IO simulation");
  out.push_back(
      extra(0x3510, 1, 9, DataType::unsigned32, Access::rw, "Virtual inputs", "MovingCap IO simulation", num(0)));
  out.push_back(extra(0x3510, 2, 9, DataType::unsigned16, Access::rw, "Input function command",
                      "MovingCap IO simulation", num(0)));
  const std::string_view nvm = "NVM statistics";
  add_record_head(out, 0x5006, 5, nvm);
  out.push_back(extra(0x5006, 1, 9, DataType::unsigned8, Access::ro, "MEM lastSharedMemAccess Status", nvm, num(1)));
  out.push_back(extra(0x5006, 2, 9, DataType::unsigned8, Access::ro, "MEM lastSharedMemBankUsed", nvm, num(1)));
  out.push_back(extra(0x5006, 3, 9, DataType::unsigned8, Access::ro, "MEM eventCount", nvm, num(0)));
  out.push_back(extra(0x5006, 4, 9, DataType::unsigned8, Access::ro, "MEM errorEventCount", nvm, num(0)));
  out.push_back(extra(0x5006, 5, 9, DataType::integer32, Access::ro, "MEM writeCycle", nvm, num(0)));
  // 5007h/5008h IP address and mask (missing from MCFLAT and MCN23).
  if (!has(0x5007)) {
    add_record_head(out, 0x5007, 4, "ip address");
    for (std::uint8_t s = 1; s <= 4; ++s) {
      out.push_back(extra(0x5007, s, 9, DataType::unsigned8, s == 1 ? Access::ro : Access::rw, k_ip_names[s - 1],
                          "ip address", num(0)));
    }
  }
  if (!has(0x5008)) {
    add_record_head(out, 0x5008, 4, "subnet mask");
    for (std::uint8_t s = 1; s <= 4; ++s) {
      out.push_back(extra(0x5008, s, 9, DataType::unsigned8, s == 1 ? Access::ro : Access::rw, k_mask_names[s - 1],
                          "subnet mask", num(0)));
    }
  }
  // 6062h position demand value (every model); 60B8h touch probe function (standard models).
  out.push_back(
      extra(0x6062, 0, 7, DataType::integer32, Access::ro, "Position demand value", "Position demand value", num(0)));
  if (!p.is_rabbit() && !has(0x60B8)) {
    const std::string_view n = "Touch probe function";
    out.push_back(extra(0x60B8, 0, 7, DataType::unsigned16, Access::rw, n, n, num(0)));
  }
  // 3300h/3301h RABBIT motor and control parameters.
  if (p.base == Base::mcflat) {
    const std::string_view m = "RABBIT motor parameters";
    add_record_head(out, 0x3300, 7, m);
    out.push_back(extra(0x3300, 0x04, 9, DataType::unsigned16, Access::rw, "motor_imbalance_amplitude", m, num(0)));
    out.push_back(extra(0x3300, 0x05, 9, DataType::integer16, Access::rw, "motor_imbalance_angle", m, num(0)));
    out.push_back(extra(0x3300, 0x07, 9, DataType::integer16, Access::rw, "motor_weight", m, num(0)));
    const std::string_view c = "RABBIT control parameters";
    add_record_head(out, 0x3301, 15, c);
    out.push_back(extra(0x3301, 0x01, 9, DataType::unsigned16, Access::rw, "control_mode", c, num(1)));
    out.push_back(extra(0x3301, 0x04, 9, DataType::unsigned16, Access::rw, "mass_payload", c, num(0)));
    out.push_back(extra(0x3301, 0x06, 9, DataType::integer16, Access::rw, "k0 pos gain", c, num(0)));
    out.push_back(extra(0x3301, 0x07, 9, DataType::integer16, Access::rw, "k1 vel gain", c, num(0)));
    out.push_back(extra(0x3301, 0x08, 9, DataType::integer16, Access::rw, "k2 err gain", c, num(0)));
    out.push_back(extra(0x3301, 0x0E, 9, DataType::integer16, Access::rw, "deceleration_tuning", c, num(0)));
    out.push_back(extra(0x3301, 0x0F, 9, DataType::integer16, Access::rw, "weight_compensation", c, num(0)));
  }
  // 3401h.1F–.25 absolute-encoder diagnostics (MC349_AE).
  if (p.ae_extras && !has_entry(0x3401, 0x1F)) {
    const std::string_view g = "Gateway control parameters";
    out.push_back(extra(0x3401, 0x1F, 9, DataType::integer16, Access::ro, "external multiturn pos", g, num(0)));
    out.push_back(extra(0x3401, 0x20, 9, DataType::unsigned16, Access::ro, "external singleturn pos", g, num(0)));
    out.push_back(extra(0x3401, 0x21, 9, DataType::unsigned32, Access::ro, "SPI errors", g, num(0)));
    out.push_back(extra(0x3401, 0x22, 9, DataType::unsigned32, Access::rw, "home offset compensation", g, num(0)));
    out.push_back(extra(0x3401, 0x23, 9, DataType::integer32, Access::rw, "phase offset", g, num(0)));
    out.push_back(extra(0x3401, 0x24, 9, DataType::integer16, Access::rw, "encoder multiturn pos offset", g, num(0)));
    out.push_back(extra(0x3401, 0x25, 9, DataType::integer32, Access::ro, "rotary overflow counter", g, num(0)));
  }
}

// object-dictionary.md §2.6
EntryClass class_of(const EntryInfo& e, Base base) {
  const std::uint16_t i = e.index;
  const std::uint8_t s = e.sub;
  // commands
  if ((i == 0x1003 && s == 0) || ((i == 0x1010 || i == 0x1011) && s >= 1) || (i == 0x1F51 && s == 1) ||
      (i == 0x2000 && s == 1) || (i == 0x3010 && s == 1) || (i == 0x3500 && s == 2) || (i == 0x3510 && s == 2)) {
    return EntryClass::cmd;
  }
  // process data and diagnostic access
  if (i == 0x6040 || i == 0x6060 || i == 0x607A || i == 0x60FF || (i == 0x60FE && s == 1) || (i == 0x3510 && s == 1) ||
      (i == 0x3401 && s == 0x19) || (i == 0x2000 && s == 3) || (i == 0x5000 && (s == 2 || s == 4)) ||
      (i == 0x5001 && s >= 1) || (i == 0x5002 && s >= 1 && e.access == Access::rw)) {
    return EntryClass::proc;
  }
  if (i == 0x5000 && s == 0) return EntryClass::const_;
  // network identity entries that the XDD makes read-only are still parameters
  if ((i == 0x5007 || i == 0x5008) && s >= 1) return EntryClass::param;
  if (e.access == Access::const_) return EntryClass::const_;
  if (e.access == Access::ro) {
    if (e.object_code != 7 && s == 0) return EntryClass::const_;
    if (i == 0x1000 || i == 0x1018 || i == 0x1200 || in(i, 0x1600, 0x1603) || in(i, 0x1A00, 0x1A03) ||
        (i == 0x3404 && s == 4) || in(i, 0x6402, 0x6407) || i == 0x6502 || i == 0x6503 || i == 0x67FF || i == 0x300A) {
      return EntryClass::const_;
    }
    return EntryClass::live;
  }
  (void)base;
  if (in(i, 0x1000, 0x1FFF) && i != 0x1029) return EntryClass::comm;
  return EntryClass::param;
}

// ---- §5 limits -------------------------------------------------------------------------------

bool restricted_can_id(std::int64_t id) {
  return (id >= 0x000 && id <= 0x07F) || (id >= 0x101 && id <= 0x180) || (id >= 0x581 && id <= 0x5FF) ||
         (id >= 0x601 && id <= 0x67F) || (id >= 0x6E0 && id <= 0x6FF) || (id >= 0x701 && id <= 0x7FF);
}

// COB-ID rules of slcan-canopen.md §9.2 (PDOs, EMCY).
AbortCode cob_id_validator(const ObjectDictionary&, std::optional<std::int64_t> stored, std::int64_t v) {
  if (v & 0x3FFFF800LL) return AbortCode::invalid_value;  // bit 29 and bits 28…11
  const bool valid = (v & 0x80000000LL) == 0;
  if (stored && valid && (*stored & 0x80000000LL) == 0 && (*stored & 0x7FF) != (v & 0x7FF)) {
    return AbortCode::invalid_value;
  }
  if (valid && restricted_can_id(v & 0x7FF)) return AbortCode::invalid_value;
  return AbortCode::none;
}

// One rule of §5: entries first…last (sub = k_any_sub, k_subs_from_1 or one sub) get `apply`. A
// table instead of a chain of ifs per entry: building a drive visits the ~40 matching entries, not
// ~900 entries × ~50 conditions (issue 26). Rows apply in order; a later row overrides an earlier
// one for the same entry.
constexpr int k_any_sub = -1;
constexpr int k_subs_from_1 = -2;
struct LimitRule {
  std::uint16_t first;
  std::uint16_t last;
  int sub;
  void (*apply)(EntryInfo& e, const model::ModelPreset& p);
};

template <std::int64_t Lo, std::int64_t Hi>
void range(EntryInfo& e, const model::ModelPreset&) {
  e.limits = Range{Lo, Hi};
}
template <auto MakeValidator>
void validate(EntryInfo& e, const model::ModelPreset&) {
  e.validator = MakeValidator();
}
void length_tolerant(EntryInfo& e, const model::ModelPreset&) { e.length_tolerant = true; }

constexpr std::array<LimitRule, 36> k_limit_rules = {{
    {0x3401, 0x3401, 0x06, range<-1, 1>},
    {0x6067, 0x6067, k_any_sub, range<0, 2147483648LL>},
    {0x606D, 0x6070, k_any_sub, range<1, 65535>},
    {0x607A, 0x607A, k_any_sub, range<-2147483647LL, 2147483647LL>},
    {0x607D, 0x607D, k_subs_from_1, range<-2147483647LL, 2147483647LL>},
    {0x6083, 0x6085, k_any_sub, range<1, 4294967295LL>},
    {0x609A, 0x609A, k_any_sub, range<1, 4294967295LL>},
    {0x60C5, 0x60C6, k_any_sub, range<1, 4294967295LL>},
    {0x608F, 0x608F, k_subs_from_1, range<1, 4294967295LL>},
    {0x6091, 0x6092, k_subs_from_1, range<1, 4294967295LL>},
    {0x6060, 0x6060, k_any_sub,
     [](EntryInfo& e, const model::ModelPreset& p) { e.validator = p.is_rabbit() ? one_of<0, 1, 6>() : one_of<0, 1, 3, 6>(); }},
    {0x605A, 0x605A, k_any_sub, validate<one_of<0, 1, 2, 5, 6>>},
    {0x605B, 0x605C, k_any_sub, validate<one_of<0, 1>>},
    {0x605D, 0x605E, k_any_sub, validate<one_of<0, 1, 2, 3, 4>>},
    {0x1005, 0x1005, k_any_sub,
     [](EntryInfo& e, const model::ModelPreset&) {
       e.validator = [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
         if (v & 0x7FFFF800LL) return AbortCode::invalid_value;  // bit 30 (producer), 29, 28…11
         if (restricted_can_id(v & 0x7FF)) return AbortCode::invalid_value;
         return AbortCode::none;
       };
     }},
    {0x1400, 0x1403, 1, [](EntryInfo& e, const model::ModelPreset&) { e.validator = cob_id_validator; }},
    {0x1800, 0x1803, 1, [](EntryInfo& e, const model::ModelPreset&) { e.validator = cob_id_validator; }},
    {0x1014, 0x1014, k_any_sub, [](EntryInfo& e, const model::ModelPreset&) { e.validator = cob_id_validator; }},
    {0x1400, 0x1403, 2, validate<range_set<0, 240, 254, 255>>},
    {0x1800, 0x1803, 2, validate<range_set<0, 240, 252, 253, 254, 255>>},
    {0x1800, 0x1803, 3,
     [](EntryInfo& e, const model::ModelPreset&) {
       // the inhibit time may change only while the PDO is invalid (its COB-ID in sub 1 of the same object)
       const std::uint16_t comm = e.index;
       e.validator = [comm](const ObjectDictionary& od, std::optional<std::int64_t> stored, std::int64_t) {
         if (!stored) return AbortCode::none;
         return (od.number(comm, 1) & 0x80000000LL) ? AbortCode::none : AbortCode::invalid_value;
       };
     }},
    {0x1029, 0x1029, 1, validate<one_of<0, 1, 2>>},
    {0x1F51, 0x1F51, 1, validate<one_of<0, 1, 2, 3>>},
    {0x3404, 0x3404, 3, range<1, 127>},
    {0x3500, 0x3500, 2, validate<one_of<0, 1, 2>>},
    {0x3500, 0x3500, 4, validate<one_of<0, 1>>},
    {0x3511, 0x351A, 1,
     [](EntryInfo& e, const model::ModelPreset&) {
       e.validator = [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
         return ((v >> 8) & 0xFF) <= 11 && (v & 0xFF) <= 11 ? AbortCode::none : AbortCode::invalid_value;
       };
     }},
    {0x3511, 0x351A, 5, length_tolerant},
    {0x3511, 0x351A, 7, length_tolerant},
    {0x3611, 0x3614, 2, length_tolerant},
    {0x3510, 0x3510, 2,
     [](EntryInfo& e, const model::ModelPreset&) {
       e.validator = [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
         const std::int64_t yy = (v >> 8) & 0xFF;
         const std::int64_t zz = v & 0xFF;
         if (zz == 0) return AbortCode::none;
         return yy >= 1 && yy <= 10 && zz <= 8 ? AbortCode::none : AbortCode::invalid_value;
       };
     }},
    {0x3611, 0x3614, 1, validate<range_set<0, 6>>},
    {0x5000, 0x5000, 0, validate<one_of<5>>},
    {0x60B8, 0x60B8, k_any_sub,
     [](EntryInfo& e, const model::ModelPreset&) {
       e.validator = [](const ObjectDictionary&, std::optional<std::int64_t>, std::int64_t v) {
         if (v & 0xF000) return AbortCode::invalid_value;
         for (int shift : {0, 4, 8}) {
           if (((v >> shift) & 0xF) > 10) return AbortCode::invalid_value;
         }
         return AbortCode::none;
       };
     }},
    {0x3300, 0x3300, 5, range<-180, 180>},
    {0x3301, 0x3301, 1, validate<one_of<1, 2, 3>>},
}};

// `entries` sorted by (index, sub).
void apply_limits(std::vector<EntryInfo>& entries, const model::ModelPreset& p) {
  for (const LimitRule& r : k_limit_rules) {
    auto it = std::lower_bound(entries.begin(), entries.end(), r.first,
                               [](const EntryInfo& e, std::uint16_t index) { return e.index < index; });
    for (; it != entries.end() && it->index <= r.last; ++it) {
      if (r.sub == k_any_sub || (r.sub == k_subs_from_1 ? it->sub >= 1 : it->sub == r.sub)) r.apply(*it, p);
    }
  }
}

// ---- §7 factory values -------------------------------------------------------------------------

// `entries` sorted by (index, sub) (sort_entries).
void set_factory(std::vector<EntryInfo>& entries, std::uint16_t index, std::uint8_t sub, Value v) {
  const auto it = std::lower_bound(entries.begin(), entries.end(), std::pair{index, sub},
                                   [](const EntryInfo& e, const std::pair<std::uint16_t, std::uint8_t>& k) {
                                     return e.index != k.first ? e.index < k.first : e.sub < k.second;
                                   });
  if (it != entries.end() && it->index == index && it->sub == sub) it->factory = std::move(v);
}

void apply_factory(std::vector<EntryInfo>& out, const model::ModelPreset& p) {
  const auto f = [&](std::uint16_t i, std::uint8_t s, std::int64_t v) { set_factory(out, i, s, Value{v}); };
  const auto str = [&](std::uint16_t i, std::uint8_t s, std::string v) { set_factory(out, i, s, Value{std::move(v)}); };
  const auto& id = p.identity;
  str(0x1008, 0, id.device_name);
  str(0x1009, 0, id.hardware_version);
  str(0x100A, 0, id.software_version);
  for (std::uint8_t s = 1; s <= 3; ++s) {
    f(0x1010, s, 1);
    f(0x1011, s, 1);
  }
  f(0x1014, 0, 0x80 + k_factory_node_id);
  f(0x1018, 1, id.vendor_id);
  f(0x1018, 2, id.product_code);
  f(0x1018, 3, id.revision);
  f(0x1018, 4, id.serial);
  f(0x1600, 0, 1);
  f(0x1601, 0, 2);
  f(0x1602, 0, 2);
  f(0x1603, 0, 2);
  f(0x1603, 2, 0x60FF0020);
  f(0x3010, 1, 1);
  f(0x3401, 1, 100);
  f(0x3401, 2, 10);
  f(0x3401, 3, 1000);
  f(0x3401, 4, 150);
  f(0x3401, 0x15, 1000);
  f(0x3401, 0x16, 1000);
  f(0x3401, 0x17, 20000);
  f(0x3401, 0x18, 1000);
  f(0x3401, 0x1B, 200);
  if (p.base == Base::mc349) f(0x3401, 0x1C, 65536);
  if (p.base == Base::mc6xx || p.base == Base::mcflat) {
    f(0x3401, 0x0D, 4);      // pole pairs [choice, docs/decisions/0003]
    f(0x3401, 0x0E, 16384);  // encoder increments, 4× evaluation [choice]
  }
  if (p.ae_extras) f(0x3401, 0, 0x25);
  f(0x3404, 3, k_factory_node_id);
  f(0x3404, 4, id.serial);
  f(0x3500, 0, 6);
  str(0x3500, 1, "(empty)");
  for (std::uint16_t in = 0x3511; in <= 0x351A; ++in) {
    f(in, 6, 200);
    f(in, 7, 2000);
    f(in, 9, 2000);
    f(in, 0x0A, 1000);
  }
  for (std::uint16_t o = 0x3611; o <= 0x3614; ++o) {
    f(o, 3, 1000);
    f(o, 4, -1000);
    f(o, 5, 100);
    f(o, 6, 100);
  }
  const std::int64_t ip[4] = {192, 168, 2, 150};
  const std::int64_t mask[4] = {255, 255, 255, 0};
  for (std::uint8_t s = 1; s <= 4; ++s) {
    f(0x5007, s, ip[s - 1]);
    f(0x5008, s, mask[s - 1]);
  }
  f(0x5000, 0, 5);
  str(0x300A, 0, "V1.00");
  f(0x6041, 0, 0x0040);
  f(0x6073, 0, 1000);
  f(0x6081, 0, p.kind == model::Kind::linear ? 100000 : 1000);
  f(0x6059, 1, 0);
  f(0x6059, 2, -200000);
  f(0x6059, 3, 100);
  f(0x607D, 1, 0);
  f(0x607D, 2, 0);
  f(0x608F, 1, p.encoder_inc);
  f(0x6502, 0, p.supported_modes);
  f(0x67FF, 0, 0x00020192);
  for (const auto& [key, v] : p.factory_values) f(key.index, key.sub, v);
}

}  // namespace

std::span<const tables::XddEntry> xdd_table(model::Base base) {
  switch (base) {
    case Base::mc349: return tables::xdd_mc349();
    case Base::mc6xx: return tables::xdd_mc6xx();
    case Base::mcflat: return tables::xdd_mcflat();
    case Base::mcn23: return tables::xdd_mcn23();
    case Base::faulhaber: return {};  // hand-written: drive/od/faulhaber_table.cpp
  }
  return {};
}

std::vector<EntryInfo> build_entries(const model::ModelPreset& preset) {
  if (preset.is_faulhaber()) return build_faulhaber_entries(preset);
  const auto table = xdd_table(preset.base);
  std::vector<EntryInfo> extras;
  extras.reserve(160);
  add_extras(extras, table, preset);
  sort_entries(extras);
  // One merge of the sorted XDD table and the sorted additions: each entry is built once in its
  // place (a sort of all ~630 entries moved each several times, issue 26).
  std::vector<EntryInfo> out;
  out.reserve(table.size() + extras.size());
  auto x = table.begin();
  auto add = extras.begin();
  while (x != table.end() || add != extras.end()) {
    const bool take_xdd = add == extras.end() ||
                          (x != table.end() && (x->index != add->index ? x->index < add->index : x->sub < add->sub));
    if (take_xdd) {
      out.push_back(from_xdd(*x++));
    } else {
      out.push_back(std::move(*add++));
    }
  }
  for (auto& e : out) e.cls = class_of(e, preset.base);
  apply_limits(out, preset);
  apply_factory(out, preset);
  return out;
}

ObjectDictionary::ObjectDictionary(const model::ModelPreset& preset)
    : ObjectDictionary(preset_layout(preset, 0, [&] { return build_entries(preset); })) {}

}  // namespace mcemu::od
