// The EDS text itself (slcan-canopen.md §12 EDS-01; the full per-preset comparison with --dump-od
// runs against the binary in tests/integration/test_eds.py): section layout of CiA 306, values
// in the notation readers expect, one section per entry.
#include "protocols/canopen/eds.hpp"

#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "drive/model/model_preset.hpp"
#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen {
namespace {

using Sections = std::map<std::string, std::map<std::string, std::string>>;

Sections parse(const std::string& text) {
  Sections out;
  std::istringstream in(text);
  std::string line;
  std::string current;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line.front() == '[') {
      current = line.substr(1, line.size() - 2);
      EXPECT_FALSE(out.count(current)) << "duplicate section " << current;
      out[current];
      continue;
    }
    const auto eq = line.find('=');
    EXPECT_NE(eq, std::string::npos) << line;
    out[current][line.substr(0, eq)] = line.substr(eq + 1);
  }
  return out;
}

EdsInfo info() { return EdsInfo{"MC349.eds", "Fullmo GmbH", "test", "11-23-2026", "03:47PM"}; }

TEST(Eds, LayoutAndValuesOfMc349) {
  const auto preset = *model::find_preset("MC349");
  od::ObjectDictionary od(preset);
  const auto s = parse(make_eds(od, info()));
  EXPECT_EQ(s.at("FileInfo").at("CreationDate"), "11-23-2026");
  EXPECT_EQ(s.at("FileInfo").at("EDSVersion"), "4.0");
  EXPECT_EQ(s.at("DeviceInfo").at("VendorNumber"), "0x0000053B");
  EXPECT_EQ(s.at("DeviceInfo").at("ProductName"), "MC349_ETH_RE");
  EXPECT_EQ(s.at("MandatoryObjects").at("SupportedObjects"), "3");
  EXPECT_EQ(s.at("MandatoryObjects").at("3"), "0x1018");
  // VAR: one section; numbers in hex, negative ones decimal
  EXPECT_EQ(s.at("6041").at("DataType"), "0x0006");
  EXPECT_EQ(s.at("6041").at("AccessType"), "ro");
  EXPECT_EQ(s.at("6041").at("PDOMapping"), "1");
  EXPECT_EQ(s.at("6083").at("DefaultValue"), "0x3E8");
  EXPECT_EQ(s.at("6083").at("LowLimit"), "0x1");
  EXPECT_EQ(s.at("607A").at("LowLimit"), "-2147483647");
  EXPECT_EQ(s.at("1008").at("DefaultValue"), "MC349_ETH_RE");
  EXPECT_EQ(s.at("1008").at("DataType"), "0x0009");
  // RECORD: a head with SubNumber, then hex-named sub sections
  EXPECT_EQ(s.at("1018").at("ObjectType"), "0x9");
  EXPECT_EQ(s.at("1018").at("SubNumber"), "5");
  EXPECT_EQ(s.at("1018sub2").at("DefaultValue"), "0x32");
  EXPECT_EQ(s.at("1A00sub1").at("DefaultValue"), "0x60410010");
  EXPECT_FALSE(s.count("1018sub5"));
  // every entry of the dictionary has its section, and there is nothing else
  std::size_t entry_sections = 0;
  for (const auto& [name, keys] : s) entry_sections += keys.count("DataType");
  EXPECT_EQ(entry_sections, od.size());
  for (const auto& [name, keys] : s) {
    if (keys.count("ParameterName")) {
      EXPECT_EQ(keys.at("ParameterName").find(';'), std::string::npos) << name;
    }
  }
}

TEST(Eds, CurrentValuesAndOneLineStrings) {
  // A test dictionary: a string with a line break must not break the file; values are current.
  const auto preset = *model::find_preset("MC349");
  auto entries = test::extended_entries(preset);
  od::ObjectDictionary od(std::move(entries));
  ASSERT_EQ(od.write(0x2F00, 0, od::Value{std::string("two\r\nlines")}, od::Origin::internal), od::AbortCode::none);
  ASSERT_EQ(od.write(0x6083, 0, od::Value{std::int64_t{2500}}, od::Origin::internal), od::AbortCode::none);
  const auto s = parse(make_eds(od, info()));
  EXPECT_EQ(s.at("2F00").at("DefaultValue"), "two  lines");
  EXPECT_EQ(s.at("6083").at("DefaultValue"), "0x9C4");
  EXPECT_EQ(s.at("2F01").at("AccessType"), "wo");
  EXPECT_EQ(s.at("ManufacturerObjects").count("SupportedObjects"), 1u);
}

}  // namespace
}  // namespace mcemu::canopen
