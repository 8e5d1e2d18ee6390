// Dynamic PDO mapping mode (slcan-canopen.md §9.7; conformance PDO-29 … PDO-33).
#include "protocols/canopen/dynamic_mapping.hpp"

#include <gtest/gtest.h>

#include "protocols/canopen/comm_reload.hpp"
#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

struct DynamicHarness : Harness {
  std::unique_ptr<DynamicMapping> mapping;
  std::vector<od::StoredValue> stored;
  DynamicHarness() : Harness("MC349", CanopenConfig{.dynamic_pdo_mapping = true}) {
    node.reset();
    auto entries = od::build_entries(preset);
    make_mapping_dynamic(entries);
    od = std::make_unique<od::ObjectDictionary>(std::move(entries));
    mapping = std::make_unique<DynamicMapping>(*od);
    Node::Hooks hooks;
    hooks.reset_communication = [this] { reload_communication_objects(*od, {}, stored); };
    node = std::make_unique<Node>(*od, CanopenConfig{.dynamic_pdo_mapping = true}, hooks);
  }
  ~DynamicHarness() {
    node.reset();
    mapping.reset();
  }
};

TEST(DynamicMapping, RemapTpdo1ToPosition) {  // PDO-29, the §9.7 example byte for byte
  DynamicHarness h;
  h.boot();
  EXPECT_EQ(h.send("t632823001801B2010080"), "t5B286000180100000000\r");
  EXPECT_EQ(h.send("t63282F001A0000000000"), "t5B2860001A0000000000\r");
  EXPECT_EQ(h.send("t632823001A0120006460"), "t5B2860001A0100000000\r");
  EXPECT_EQ(h.send("t63282F001A0001000000"), "t5B2860001A0000000000\r");
  EXPECT_EQ(h.send("t632823001801B2010000"), "t5B286000180100000000\r");
  EXPECT_EQ(h.send("t632823001A0110004160"), "t5B2880001A0130000906\r");  // entry while valid
  h.set(0x6064, 0, 30000);
  EXPECT_EQ(h.send("t00020132"), "t1B2430750000\rt2B23400000\r");  // TPDO1 now carries 4 bytes
}

TEST(DynamicMapping, WriteRules) {  // PDO-30, PDO-31, PDO-32
  DynamicHarness h;
  h.boot();
  // mapping write while valid; entry while sub 00h ≠ 0
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 0})), abort_line(0x1A00, 0, 0x06090030));
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x1A, 0x02, 0x20, 0x00, 0x64, 0x60})), abort_line(0x1A00, 2, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 0})), resp({0x60, 0x00, 0x1A, 0x00}));
  // not mappable: a string, 6041h in an RPDO, a wrong length, a missing object
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x1A, 0x01, 0x00, 0x00, 0x08, 0x10})), abort_line(0x1A00, 1, 0x06040041));
  h.send(sdo({0x23, 0x00, 0x14, 0x01, 0x32, 0x02, 0x00, 0x80}));
  h.send(sdo({0x2F, 0x00, 0x16, 0x00, 0}));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x16, 0x01, 0x10, 0x00, 0x41, 0x60})), abort_line(0x1600, 1, 0x06040041));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x16, 0x01, 0x08, 0x00, 0x40, 0x60})), abort_line(0x1600, 1, 0x06040041));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x16, 0x01, 0x10, 0x00, 0xFF, 0x6F})), abort_line(0x1600, 1, 0x06040041));
  // 72 bits → 0x06040042; 9 entries → 0x06090030; a dummy of the right length is fine
  for (std::uint8_t s = 1; s <= 3; ++s) {
    EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x1A, s, 0x20, 0x00, 0x64, 0x60})), resp({0x60, 0x00, 0x1A, s}));
  }
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 3})), abort_line(0x1A00, 0, 0x06040042));
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 9})), abort_line(0x1A00, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 4})), abort_line(0x1A00, 0, 0x06040041));  // entry 4 is zero
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x1A, 0x02, 0x08, 0x00, 0x05, 0x00})), resp({0x60, 0x00, 0x1A, 0x02}));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x1A, 0x03, 0x10, 0x00, 0x05, 0x00})), abort_line(0x1A00, 3, 0x06040041));
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 2})), resp({0x60, 0x00, 0x1A, 0x00}));
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00}));
  h.set(0x6064, 0, -2);
  EXPECT_EQ(h.send("t00020132").substr(0, 16), "t1B25FEFFFFFF00\r");  // position + dummy byte 0
}

TEST(DynamicMapping, EnablingAnEmptyMappingIsRefusedAndMappingSurvivesResetCommunication) {  // PDO-33
  DynamicHarness h;
  h.boot();
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));
  h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 0}));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00})), abort_line(0x1800, 1, 0x06090030));
  h.send(sdo({0x23, 0x00, 0x1A, 0x01, 0x20, 0x00, 0x64, 0x60}));
  h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 1}));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00})), resp({0x60, 0x00, 0x18, 0x01}));
  // "store" (1010h puts the comm class into the file), then reset communication
  h.od->for_each([&](const od::EntryInfo& e, const od::Value& v) {
    if (e.cls == od::EntryClass::comm) h.stored.push_back({e.index, e.sub, v});
  });
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));
  h.send(sdo({0x2F, 0x00, 0x1A, 0x00, 0}));
  h.send("t00028232");
  h.wait(10ms);
  EXPECT_EQ(h.number(0x1A00, 0), 1);
  EXPECT_EQ(h.number(0x1A00, 1), 0x60640020);
  EXPECT_EQ(h.number(0x1800, 1), 0x1B2);
  // the TPDO goes out with the mapping loaded (a bulk load, no write: the TPDO's resolved mapping
  // must follow it)
  h.set(0x6064, 0, 30000);
  EXPECT_EQ(h.send("t00020132").substr(0, 14), "t1B2430750000\r");
  // without storing, reset communication returns to the factory mapping
  h.stored.clear();
  h.send("t00028232");
  h.wait(10ms);
  EXPECT_EQ(h.number(0x1A00, 1), 0x60410010);
  EXPECT_EQ(h.send("t00020132").substr(0, 5), "t1B22");  // statusword alone
}

TEST(DynamicMapping, EveryMappingObjectHasEightEntries) {
  DynamicHarness h;
  for (std::uint16_t i : {0x1600, 0x1601, 0x1602, 0x1603, 0x1A00, 0x1A01, 0x1A02, 0x1A03}) {
    for (std::uint8_t s = 0; s <= 8; ++s) {
      const auto* info = h.od->info(i, s);
      ASSERT_NE(info, nullptr);
      EXPECT_EQ(info->access, od::Access::rw);
    }
    EXPECT_EQ(h.od->info(i, 9), nullptr);
  }
  EXPECT_EQ(h.number(0x1603, 2), 0x60FF0020);
}

}  // namespace
}  // namespace mcemu::canopen::test
