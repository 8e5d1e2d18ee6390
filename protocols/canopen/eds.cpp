#include "protocols/canopen/eds.hpp"

#include <cstdio>
#include <map>
#include <vector>

namespace mcemu::canopen {

namespace {

struct Object {
  std::uint16_t index = 0;
  std::vector<std::pair<const od::EntryInfo*, od::Value>> subs;  // ascending sub-index
};

std::string hex(std::uint64_t v, int digits) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%0*llX", digits, static_cast<unsigned long long>(v));
  return buf;
}

std::string index_name(std::uint16_t index) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%04X", index);
  return buf;
}

// One line of text: EDS values end at the line end.
std::string one_line(const std::string& s) {
  std::string out;
  for (char c : s) out.push_back(c == '\r' || c == '\n' ? ' ' : c);
  return out;
}

// A parameter name: python-canopen reads EDS files with ';' as inline comment start.
std::string name_text(std::string_view s) {
  std::string out = one_line(std::string(s));
  for (char& c : out) c = c == ';' ? ',' : c;
  return out;
}

std::string number(std::int64_t v) { return v < 0 ? std::to_string(v) : hex(static_cast<std::uint64_t>(v), 1); }

std::string value_text(const od::Value& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return one_line(*s);
  return number(std::get<std::int64_t>(v));
}

void entry_keys(std::string& out, const od::EntryInfo& e, const od::Value& v) {
  out += "ParameterName=" + name_text(e.name) + "\n";
  out += "ObjectType=0x7\n";
  out += "DataType=" + hex(static_cast<std::uint16_t>(e.type), 4) + "\n";
  out += "AccessType=" + std::string(od::to_string(e.access)) + "\n";  // ro, wo, rw, const
  if (e.limits) {
    out += "LowLimit=" + number(e.limits->min) + "\n";
    out += "HighLimit=" + number(e.limits->max) + "\n";
  }
  out += "DefaultValue=" + value_text(v) + "\n";
  out += "PDOMapping=" + std::string(e.pdo == od::PdoFlag::no ? "0" : "1") + "\n";
}

void object_sections(std::string& out, const Object& o) {
  const od::EntryInfo& first = *o.subs.front().first;
  const std::string name = index_name(o.index);
  out += "\n[" + name + "]\n";
  if (first.object_code == 7) {
    entry_keys(out, first, o.subs.front().second);
    return;
  }
  out += "ParameterName=" + name_text(first.object_name.empty() ? first.name : first.object_name) + "\n";
  out += "ObjectType=" + hex(first.object_code, 1) + "\n";
  out += "SubNumber=" + std::to_string(o.subs.size()) + "\n";
  for (const auto& [e, v] : o.subs) {
    char sub[8];
    std::snprintf(sub, sizeof sub, "%X", e->sub);
    out += "\n[" + name + "sub" + sub + "]\n";
    entry_keys(out, *e, v);
  }
}

bool mandatory(std::uint16_t index) { return index == 0x1000 || index == 0x1001 || index == 0x1018; }
bool manufacturer(std::uint16_t index) { return index >= 0x2000 && index <= 0x5FFF; }

void group(std::string& out, const char* section, const std::vector<const Object*>& objects) {
  out += "\n[" + std::string(section) + "]\n";
  out += "SupportedObjects=" + std::to_string(objects.size()) + "\n";
  for (std::size_t i = 0; i < objects.size(); ++i) {
    out += std::to_string(i + 1) + "=" + hex(objects[i]->index, 4) + "\n";
  }
  for (const Object* o : objects) object_sections(out, *o);
}

std::uint64_t read_or(const od::ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
  const auto r = od.read_number(index, sub);
  return r ? static_cast<std::uint64_t>(*r) : 0;
}

}  // namespace

std::string make_eds(const od::ObjectDictionary& od, const EdsInfo& info) {
  std::map<std::uint16_t, Object> objects;
  od.for_each([&](const od::EntryInfo& e, const od::Value& stored) {
    auto& o = objects[e.index];
    o.index = e.index;
    const auto r = od.read(e.index, e.sub);  // as --dump-od: read hooks apply; wo entries: stored
    o.subs.emplace_back(&e, r ? *r : stored);
  });
  std::vector<const Object*> mand;
  std::vector<const Object*> opt;
  std::vector<const Object*> mfr;
  int rpdos = 0;
  int tpdos = 0;
  for (const auto& [index, o] : objects) {
    (mandatory(index) ? mand : manufacturer(index) ? mfr : opt).push_back(&o);
    rpdos += index >= 0x1400 && index <= 0x15FF ? 1 : 0;
    tpdos += index >= 0x1800 && index <= 0x19FF ? 1 : 0;
  }
  const auto text = [&](std::uint16_t index) {
    const auto r = od.read(index, 0);
    return r && std::holds_alternative<std::string>(*r) ? one_line(std::get<std::string>(*r)) : std::string{};
  };

  std::string out;
  out += "[FileInfo]\n";
  out += "FileName=" + info.file_name + "\n";
  out += "FileVersion=1\nFileRevision=0\nEDSVersion=4.0\n";
  out += "Description=" + one_line(info.description) + "\n";
  out += "CreationTime=" + info.time + "\nCreationDate=" + info.date + "\nCreatedBy=mcemu\n";
  out += "ModificationTime=" + info.time + "\nModificationDate=" + info.date + "\nModifiedBy=mcemu\n";

  out += "\n[DeviceInfo]\n";
  out += "VendorName=" + one_line(info.vendor_name) + "\n";
  out += "VendorNumber=" + hex(read_or(od, 0x1018, 1), 8) + "\n";
  out += "ProductName=" + text(0x1008) + "\n";
  out += "ProductNumber=" + hex(read_or(od, 0x1018, 2), 8) + "\n";
  out += "RevisionNumber=" + hex(read_or(od, 0x1018, 3), 8) + "\n";
  out += "OrderCode=" + text(0x1008) + "\n";
  // The bus is virtual (SLCAN over TCP accepts every S command); the usual rates are listed.
  out += "BaudRate_10=0\nBaudRate_20=0\nBaudRate_50=0\nBaudRate_125=1\nBaudRate_250=1\nBaudRate_500=1\n";
  out += "BaudRate_800=0\nBaudRate_1000=1\n";
  out += "SimpleBootUpMaster=0\nSimpleBootUpSlave=1\n";
  out += "Granularity=0\n";
  out += "DynamicChannelsSupported=0\nGroupMessaging=0\n";
  out += "NrOfRXPDO=" + std::to_string(rpdos) + "\nNrOfTXPDO=" + std::to_string(tpdos) + "\n";
  out += "LSS_Supported=0\n";

  out += "\n[DummyUsage]\n";
  for (int i = 1; i <= 7; ++i) out += "Dummy000" + std::to_string(i) + "=0\n";

  out += "\n[Comments]\nLines=2\n";
  out += "Line1=Generated by mcemu from its object dictionary (" + info.file_name + ").\n";
  out += "Line2=COB-IDs are absolute for the node-id in use; DefaultValue = the value at export.\n";

  group(out, "MandatoryObjects", mand);
  group(out, "OptionalObjects", opt);
  group(out, "ManufacturerObjects", mfr);
  return out;
}

}  // namespace mcemu::canopen
