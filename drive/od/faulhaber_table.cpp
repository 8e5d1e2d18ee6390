#include "drive/od/faulhaber_table.hpp"

#include <array>
#include <string>

#include "drive/od/validators.hpp"

namespace mcemu::od {
namespace {

using T = DataType;
using A = Access;
using C = EntryClass;

constexpr std::uint8_t k_var = 7;
constexpr std::uint8_t k_array = 8;
constexpr std::uint8_t k_record = 9;

struct Builder {
  std::vector<EntryInfo> out;
  std::string_view object;  // name of the object being added
  std::uint8_t code = k_var;

  EntryInfo& add(std::uint16_t index, std::uint8_t sub, T type, A access, C cls, std::string_view name, Value factory,
                 PdoFlag pdo = PdoFlag::no) {
    EntryInfo e;
    e.index = index;
    e.sub = sub;
    e.object_code = code;
    e.type = type;
    e.access = access;
    e.pdo = pdo;
    e.cls = cls;
    e.object_name = code == k_var ? name : object;
    e.name = name;
    e.factory = std::move(factory);
    e.from_xdd = false;
    out.push_back(std::move(e));
    return out.back();
  }
  // A VAR object at sub-index 0.
  EntryInfo& var(std::uint16_t index, T type, A access, C cls, std::string_view name, std::int64_t factory,
                 PdoFlag pdo = PdoFlag::no) {
    code = k_var;
    return add(index, 0, type, access, cls, name, Value{factory}, pdo);
  }
  // Starts an ARRAY or RECORD: sub-index 0 = highest sub-index, const.
  void begin(std::uint16_t index, std::uint8_t object_code, std::string_view name, std::int64_t highest) {
    code = object_code;
    object = name;
    add(index, 0, T::unsigned8, A::ro, C::const_, "Highest Sub-index", Value{highest});
  }
};

void cia301(Builder& b, const model::ModelPreset& p) {
  const auto& id = p.identity;
  b.var(0x1000, T::unsigned32, A::ro, C::const_, "Device Type", 0x00020192);
  b.var(0x1001, T::unsigned8, A::ro, C::live, "Error Register", 0);
  b.begin(0x1003, k_array, "Pre-defined Error Field", 0);
  b.out.back().access = A::rw;  // write 0 clears the history (object-dictionary.md §2.4)
  b.out.back().cls = C::cmd;
  b.out.back().name = "Number of Errors";
  for (std::uint8_t s = 1; s <= 4; ++s)
    b.add(0x1003, s, T::unsigned32, A::ro, C::live, "Standard Error Field", Value{0});
  b.code = k_var;
  b.add(0x1008, 0, T::visible_string, A::const_, C::const_, "Manufacturer Device Name", Value{id.device_name});
  b.add(0x100A, 0, T::visible_string, A::const_, C::const_, "Manufacturer Software Version",
        Value{id.software_version});
  // Store / restore parameters (CiA 301 §7.5.2.13/14): "save" / "load" signatures, as on every
  // CiA 301 drive; the MC V3.0 keeps its parameters in EEPROM this way (AN165 warns about its write
  // cycles). Sub-index 1 all, 2 communication, 3 application parameters.
  b.begin(0x1010, k_array, "Store parameters", 3);
  b.add(0x1010, 1, T::unsigned32, A::rw, C::cmd, "save all parameters", Value{1});
  b.add(0x1010, 2, T::unsigned32, A::rw, C::cmd, "save communication parameters", Value{1});
  b.add(0x1010, 3, T::unsigned32, A::rw, C::cmd, "save application parameters", Value{1});
  b.begin(0x1011, k_array, "Restore default parameters", 3);
  b.add(0x1011, 1, T::unsigned32, A::rw, C::cmd, "restore all default parameters", Value{1});
  b.add(0x1011, 2, T::unsigned32, A::rw, C::cmd, "restore communication default parameters", Value{1});
  b.add(0x1011, 3, T::unsigned32, A::rw, C::cmd, "restore application default parameters", Value{1});
  b.begin(0x1018, k_record, "Identity Object", 4);
  b.add(0x1018, 1, T::unsigned32, A::ro, C::const_, "Vendor-ID", Value{std::int64_t{id.vendor_id}});
  b.add(0x1018, 2, T::unsigned32, A::ro, C::const_, "Product Code", Value{std::int64_t{id.product_code}});
  b.add(0x1018, 3, T::unsigned32, A::ro, C::const_, "Revision Number", Value{std::int64_t{id.revision}});
  b.add(0x1018, 4, T::unsigned32, A::ro, C::const_, "Serial Number", Value{std::int64_t{id.serial}});
}

// 3005h.01…1A (faulhaber.md §8): names with the storage of the process (EntryInfo names are views).
constexpr std::array<const char*, 26> k_variable_names = {
    "Variable a", "Variable b", "Variable c", "Variable d", "Variable e", "Variable f", "Variable g",
    "Variable h", "Variable i", "Variable j", "Variable k", "Variable l", "Variable m", "Variable n",
    "Variable o", "Variable p", "Variable q", "Variable r", "Variable s", "Variable t", "Variable u",
    "Variable v", "Variable w", "Variable x", "Variable y", "Variable z"};

void faulhaber_objects(Builder& b) {
  b.begin(0x2310, k_record, "Digital Input Settings", 0x11);
  b.add(0x2310, 0x01, T::unsigned8, A::rw, C::param, "Negative Limit Switch", Value{0});
  b.add(0x2310, 0x02, T::unsigned8, A::rw, C::param, "Positive Limit Switch", Value{0});
  b.add(0x2310, 0x03, T::integer16, A::rw, C::param, "Limit Switch Option Code", Value{1});
  b.add(0x2310, 0x04, T::unsigned8, A::rw, C::param, "Homing Switch", Value{0});
  b.add(0x2310, 0x10, T::unsigned16, A::rw, C::param, "Polarity", Value{0});
  b.add(0x2310, 0x11, T::unsigned8, A::rw, C::param, "Threshold", Value{0});
  b.begin(0x2311, k_record, "Digital I/Os", 4);
  b.add(0x2311, 0x01, T::unsigned16, A::ro, C::live, "Logical Input State", Value{0});
  b.add(0x2311, 0x02, T::unsigned16, A::ro, C::live, "Physical Input State", Value{0});
  b.add(0x2311, 0x03, T::unsigned16, A::ro, C::live, "Output State", Value{0});
  b.add(0x2311, 0x04, T::unsigned16, A::rw, C::proc, "Set Digital Outputs", Value{0xFFFF});
  b.var(0x2320, T::unsigned16, A::ro, C::live, "Error Word", 0, PdoFlag::tpdo);
  b.begin(0x2321, k_record, "Error Mask", 2);
  b.add(0x2321, 0x01, T::unsigned16, A::rw, C::param, "Emergency Mask", Value{0xFFFF});
  b.add(0x2321, 0x02, T::unsigned16, A::rw, C::param, "Fault Mask", Value{0xFFFF});
  b.begin(0x2324, k_record, "Device Status", 2);
  b.add(0x2324, 0x01, T::unsigned32, A::ro, C::live, "Device Status Word", Value{0}, PdoFlag::tpdo);
  b.add(0x2324, 0x02, T::unsigned16, A::rw, C::param, "Limit Check Delay Time", Value{200});
  b.begin(0x2400, k_record, "RS232 Settings", 8);
  b.add(0x2400, 0x03, T::unsigned8, A::rw, C::param, "Node-ID", Value{1});
  b.add(0x2400, 0x04, T::unsigned32, A::rw, C::param, "Communication Settings", Value{0x00030000});
  b.add(0x2400, 0x05, T::unsigned8, A::rw, C::param, "Net Mode", Value{0}).validator = one_of<0, 1>();
  b.add(0x2400, 0x08, T::unsigned16, A::rw, C::param, "Explicit Device ID", Value{0});
  b.begin(0x3005, k_array, "Program Variables", 26);
  b.out.back().name = "Number of Variables";
  for (std::uint8_t s = 1; s <= 26; ++s) {
    b.add(0x3005, s, T::integer32, A::rw, C::proc, k_variable_names[s - 1], Value{0});
  }
}

void cia402(Builder& b, const model::ModelPreset& p) {
  const auto range = [](EntryInfo& e, std::int64_t lo, std::int64_t hi) { e.limits = Range{lo, hi}; };
  const PdoFlag rx = PdoFlag::rpdo;
  const PdoFlag tx = PdoFlag::tpdo;
  b.var(0x603F, T::unsigned16, A::ro, C::live, "Error Code", 0, tx);
  b.var(0x6040, T::unsigned16, A::rw, C::proc, "Controlword", 0, rx);
  b.var(0x6041, T::unsigned16, A::ro, C::live, "Statusword", 0x0040, tx);
  b.var(0x605A, T::integer16, A::rw, C::param, "Quick Stop Option Code", 2).validator = one_of<0, 1, 2, 5, 6>();
  b.var(0x605B, T::integer16, A::rw, C::param, "Shutdown Option Code", 1).validator = one_of<0, 1>();
  b.var(0x605C, T::integer16, A::rw, C::param, "Disable Operation Option Code", 1).validator = one_of<0, 1>();
  b.var(0x605D, T::integer16, A::rw, C::param, "Halt Option Code", 1).validator = one_of<0, 1, 2, 3, 4>();
  b.var(0x605E, T::integer16, A::rw, C::param, "Fault Reaction Option Code", 1).validator = one_of<0, 1, 2, 3, 4>();
  // faulhaber.md §7.2: PP, PV and homing; the other FAULHABER modes answer 0x06090030
  b.var(0x6060, T::integer8, A::rw, C::proc, "Modes of Operation", 0, rx).validator = one_of<0, 1, 3, 6>();
  b.var(0x6061, T::integer8, A::ro, C::live, "Modes of Operation Display", 0, tx);
  b.var(0x6062, T::integer32, A::ro, C::live, "Position Demand Value", 0, tx);
  b.var(0x6063, T::integer32, A::ro, C::live, "Position Actual Internal Value", 0, tx);
  b.var(0x6064, T::integer32, A::ro, C::live, "Position Actual Value", 0, tx);
  range(b.var(0x6067, T::unsigned32, A::rw, C::param, "Position Window", 20), 0, 2147483648LL);
  b.var(0x6068, T::unsigned16, A::rw, C::param, "Position Window Time", 20);
  b.var(0x606B, T::integer32, A::ro, C::live, "Velocity Demand Value", 0, tx);
  b.var(0x606C, T::integer32, A::ro, C::live, "Velocity Actual Value", 0, tx);
  range(b.var(0x606D, T::unsigned16, A::rw, C::param, "Velocity Window", 20), 1, 65535);
  range(b.var(0x606E, T::unsigned16, A::rw, C::param, "Velocity Window Time", 20), 1, 65535);
  range(b.var(0x606F, T::unsigned16, A::rw, C::param, "Velocity Threshold", 20), 1, 65535);
  range(b.var(0x6070, T::unsigned16, A::rw, C::param, "Velocity Threshold Time", 20), 1, 65535);
  b.var(0x6071, T::integer16, A::rw, C::proc, "Target Torque", 0, rx);
  b.var(0x6072, T::unsigned16, A::rw, C::param, "Max Torque", 3000);
  b.var(0x6077, T::integer16, A::ro, C::live, "Torque Actual Value", 0, tx);
  range(b.var(0x607A, T::integer32, A::rw, C::proc, "Target Position", 0, rx), -2147483647LL, 2147483647LL);
  b.var(0x607C, T::integer32, A::rw, C::param, "Home Offset", 0);
  b.begin(0x607D, k_array, "Software Position Limit", 2);
  range(b.add(0x607D, 1, T::integer32, A::rw, C::param, "Min Position Limit", Value{0}), -2147483647LL, 2147483647LL);
  range(b.add(0x607D, 2, T::integer32, A::rw, C::param, "Max Position Limit", Value{0}), -2147483647LL, 2147483647LL);
  b.var(0x607E, T::unsigned8, A::rw, C::param, "Polarity", 0);
  b.var(0x607F, T::unsigned32, A::rw, C::param, "Max Profile Velocity", 10000);
  b.var(0x6080, T::unsigned32, A::rw, C::param, "Max Motor Speed", 10000);
  b.var(0x6081, T::unsigned32, A::rw, C::param, "Profile Velocity", 1000, rx);
  // faulhaber.md §7.3: 1 … 30000 (6085h up to 32750), 1 unit = 1 motor revolution/s²
  range(b.var(0x6083, T::unsigned32, A::rw, C::param, "Profile Acceleration", 1000, rx), 1, 30000);
  range(b.var(0x6084, T::unsigned32, A::rw, C::param, "Profile Deceleration", 1000, rx), 1, 30000);
  range(b.var(0x6085, T::unsigned32, A::rw, C::param, "Quick Stop Deceleration", 3000), 1, 32750);
  const std::int64_t u32_max = 4294967295LL;
  b.begin(0x608F, k_array, "Position Encoder Resolution", 2);
  range(b.add(0x608F, 1, T::unsigned32, A::rw, C::param, "Encoder Increments", Value{std::int64_t{p.encoder_inc}}), 1,
        u32_max);
  range(b.add(0x608F, 2, T::unsigned32, A::rw, C::param, "Motor Revolutions", Value{1}), 1, u32_max);
  b.begin(0x6091, k_array, "Gear Ratio", 2);
  range(b.add(0x6091, 1, T::unsigned32, A::rw, C::param, "Motor Revolutions", Value{1}), 1, u32_max);
  range(b.add(0x6091, 2, T::unsigned32, A::rw, C::param, "Shaft Revolutions", Value{1}), 1, u32_max);
  b.begin(0x6092, k_array, "Feed Constant", 2);
  range(b.add(0x6092, 1, T::unsigned32, A::rw, C::param, "Feed", Value{std::int64_t{p.encoder_inc}}), 1, u32_max);
  range(b.add(0x6092, 2, T::unsigned32, A::rw, C::param, "Shaft Revolutions", Value{1}), 1, u32_max);
  b.var(0x6098, T::integer8, A::rw, C::param, "Homing Method", 0);
  b.begin(0x6099, k_array, "Homing Speeds", 2);
  b.add(0x6099, 1, T::unsigned32, A::rw, C::param, "Speed During Search for Switch", Value{400});
  b.add(0x6099, 2, T::unsigned32, A::rw, C::param, "Speed During Search for Zero", Value{40});
  range(b.var(0x609A, T::unsigned32, A::rw, C::param, "Homing Acceleration", 1000), 1, 30000);
  b.var(0x60E0, T::unsigned16, A::rw, C::param, "Positive Torque Limit Value", 3000);
  b.var(0x60E1, T::unsigned16, A::rw, C::param, "Negative Torque Limit Value", 3000);
  b.var(0x60FC, T::integer32, A::ro, C::live, "Position Demand Internal Value", 0);
  b.var(0x60FF, T::integer32, A::rw, C::proc, "Target Velocity", 0, rx);
  b.var(0x6502, T::unsigned32, A::ro, C::const_, "Supported Drive Modes", std::int64_t{p.supported_modes});
}

}  // namespace

std::vector<EntryInfo> build_faulhaber_entries(const model::ModelPreset& preset) {
  Builder b;
  cia301(b, preset);
  faulhaber_objects(b);
  cia402(b, preset);
  // per-preset overrides (config faulhaber.node_id → 2400h.03, faulhaber.crc_check → 2400h.04 …)
  for (const auto& [key, v] : preset.factory_values) {
    for (auto& e : b.out) {
      if (e.index == key.index && e.sub == key.sub) e.factory = Value{v};
    }
  }
  return b.out;
}

}  // namespace mcemu::od
