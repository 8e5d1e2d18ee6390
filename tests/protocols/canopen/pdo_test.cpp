// PDOs and SYNC (slcan-canopen.md §8, §9; conformance PDO-01 … PDO-26, PDO-28, SYNC-01 … SYNC-09).
// A small stand-in for the drive core's 6040h hook updates 6041h inside the write, as
// drive-core.md §2.5 does, so statusword changes can be triggered by SDO and RPDO.
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

// Controlword → statusword of the CiA 402 happy path (enough for PDO tests; not the drive core).
void fake_drive(Harness& h) {
  od::ObjectDictionary& od = *h.od;
  od.on_write(0x6040, 0, [&od](od::WriteRequest& req) {
    const auto cw = std::get<std::int64_t>(req.value);
    std::int64_t sw = 0x40;
    if ((cw & 0x8F) == 0x06) sw = 0x21;
    if ((cw & 0x8F) == 0x07) sw = 0x23;
    if ((cw & 0x8F) == 0x0F) sw = 0x27;
    od.write(0x6041, 0, od::Value{sw}, od::Origin::internal);
    return od::AbortCode::none;
  });
}

std::string tpdo1(int sw) {
  char b[16];
  std::snprintf(b, sizeof b, "t1B22%02X%02X\r", sw & 0xFF, sw >> 8);
  return b;
}

TEST(Pdo, ScanMatchesTheFixedSetOnEveryPreset) {  // PDO-01
  struct Row {
    std::uint16_t index;
    std::uint8_t sub;
    std::int64_t value;
  };
  const std::vector<Row> rows = {
      {0x1400, 1, 0x232},      {0x1400, 2, 0xFF},       {0x1400, 3, 0},          {0x1401, 1, 0x332},
      {0x1401, 2, 0xFF},       {0x1402, 1, 0x432},      {0x1402, 2, 0xFF},       {0x1403, 1, 0x532},
      {0x1403, 2, 0xFF},       {0x1600, 0, 1},          {0x1600, 1, 0x60400010}, {0x1601, 0, 2},
      {0x1601, 1, 0x60400010}, {0x1601, 2, 0x60600008}, {0x1602, 0, 2},          {0x1602, 1, 0x60400010},
      {0x1602, 2, 0x607A0020}, {0x1603, 0, 2},          {0x1603, 1, 0x60400010}, {0x1603, 2, 0x60FF0020},
      {0x1800, 1, 0x1B2},      {0x1800, 2, 0xFF},       {0x1800, 3, 0},          {0x1800, 5, 0},
      {0x1801, 1, 0x2B2},      {0x1801, 2, 0xFF},       {0x1802, 1, 0x3B2},      {0x1802, 2, 0xFD},
      {0x1803, 1, 0x4B2},      {0x1803, 2, 0xFD},       {0x1A00, 0, 1},          {0x1A00, 1, 0x60410010},
      {0x1A01, 0, 2},          {0x1A01, 1, 0x60410010}, {0x1A01, 2, 0x60610008}, {0x1A02, 0, 2},
      {0x1A02, 1, 0x60410010}, {0x1A02, 2, 0x60640020}, {0x1A03, 0, 2},          {0x1A03, 1, 0x60410010},
      {0x1A03, 2, 0x606C0020},
  };
  for (auto name : model::preset_names()) {
    Harness h(name);
    h.boot();
    for (const auto& r : rows) {
      const auto v = h.od->read_number(r.index, r.sub);
      ASSERT_TRUE(v.ok()) << name << " " << std::hex << r.index << "." << int(r.sub);
      EXPECT_EQ(*v, r.value) << name << " " << std::hex << r.index << "." << int(r.sub);
    }
    for (std::uint16_t i : {0x1800, 0x1801, 0x1802, 0x1803}) {
      EXPECT_EQ(h.send(sdo({0x40, i & 0xFF, i >> 8, 4})), abort_line(i, 4, 0x06090011)) << name;
      EXPECT_EQ(h.send(sdo({0x40, i & 0xFF, i >> 8, 6})), abort_line(i, 6, 0x06090011)) << name;
    }
    EXPECT_EQ(h.send(sdo({0x40, 0x00, 0x14, 5})), abort_line(0x1400, 5, 0x06090011)) << name;
  }
}

TEST(Pdo, StatuswordChangeBySdoSendsTpdosAfterTheResponse) {  // PDO-02, §9.4 example
  Harness h;
  fake_drive(h);
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("t63282B40600006000000"), "t5B286040600000000000\rt1B222100\rt2B23210000\r");
  EXPECT_EQ(h.tick(10), "");  // no change, no frame
}

TEST(Pdo, OnlyEventDrivenTpdosOnStart) {  // PDO-03
  Harness h;
  h.boot();
  h.set(0x6041, 0, 0x0427);
  h.set(0x6064, 0, 30000);
  EXPECT_EQ(h.send("t00020132"), "t1B222704\rt2B23270400\r");
  h.set(0x6064, 0, 30001);
  EXPECT_EQ(h.tick(5), "");  // TPDO3 (253) never spontaneously
}

TEST(Pdo, NothingOutsideOperational) {  // PDO-04
  Harness h;
  fake_drive(h);
  h.boot();
  EXPECT_EQ(h.send("t63282B40600006000000"), "t5B286040600000000000\r");
  EXPECT_EQ(h.tick(3), "");
  h.send("t00020232");
  h.set(0x6041, 0, 0x23);
  EXPECT_EQ(h.tick(3), "");
  EXPECT_EQ(h.send("t0800"), "");
  EXPECT_EQ(h.send("r1B22"), "");
}

TEST(Pdo, ChangesFromOtherWritersGoOutAtTheNextStep) {  // §9.4: RefGo, web, scripts, the drive
  Harness h;
  h.boot();
  h.send("t00020132");
  h.od->write(0x6041, 0, od::Value{std::int64_t{0x21}}, od::Origin::internal);
  EXPECT_EQ(h.tick(1), "t1B222100\rt2B23210000\r");
  h.set(0x6061, 0, 1);
  EXPECT_EQ(h.tick(1), "t2B23210001\r");
}

TEST(Pdo, InhibitTime) {  // PDO-05
  Harness h;
  h.boot();
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));                          // invalid
  EXPECT_EQ(h.send(sdo({0x2B, 0x00, 0x18, 0x03, 100})), resp({0x60, 0x00, 0x18, 0x03}));  // 10 ms
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00}));                          // valid again
  EXPECT_EQ(h.send("t00020132"), tpdo1(0x40) + "t2B23400000\r");
  h.tick(20);
  const Millis t1 = h.now;
  h.set(0x6041, 0, 0x21);
  EXPECT_EQ(h.tick(1), tpdo1(0x21) + "t2B23210000\r");  // first change: at once
  h.tick(1);
  h.set(0x6041, 0, 0x23);  // 2 ms later
  h.set(0x6041, 0, 0x27);  // and again before the window ends
  h.log.clear();
  h.tick(20);
  ASSERT_EQ(h.log.size(), 2u);
  EXPECT_EQ(h.log[0].first, t1 + 3ms);
  EXPECT_EQ(h.log[0].second, "t2B23270000\r");  // TPDO2 has no inhibit time
  EXPECT_EQ(h.log[1].first, t1 + 11ms);         // exactly 10 ms after the first
  EXPECT_EQ(h.log[1].second, tpdo1(0x27));      // with the value current then
  // the node asks to be called at the window's end
  h.set(0x6041, 0, 0x21);
  h.tick(1);
  h.set(0x6041, 0, 0x23);
  h.tick(1);
  Millis sent{};
  for (const auto& [at, line] : h.log) {
    if (line.rfind("t1B2", 0) == 0) sent = at;
  }
  EXPECT_EQ(h.node->next_deadline(), sent + 10ms);
  EXPECT_EQ(h.run_until(sent + 10ms), tpdo1(0x23));
}

TEST(Pdo, InhibitSendsTheValueCurrentAtTheWindowsEnd) {  // §9.4 (CON)
  Harness h;
  h.boot();
  h.set(0x1800, 1, 0x800001B2);
  h.set(0x1800, 3, 100);
  h.set(0x1800, 1, 0x1B2);
  h.set(0x1801, 1, 0x800002B2);
  h.send("t00020132");
  h.set(0x6041, 0, 0x21);
  h.tick(2);
  h.set(0x6041, 0, 0x40);  // back to the value last sent: nothing is due at the window's end
  EXPECT_EQ(h.tick(30), "");
}

TEST(Pdo, EventTimer) {  // PDO-06
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x2B, 0x00, 0x18, 0x05, 50})), resp({0x60, 0x00, 0x18, 0x05}));  // any time
  h.send("t00020132");
  const Millis t0 = h.now;
  EXPECT_EQ(h.run_until(t0 + 49ms), "");
  EXPECT_EQ(h.run_until(t0 + 50ms), tpdo1(0x40));
  EXPECT_EQ(h.run_until(t0 + 100ms), tpdo1(0x40));
  h.wait(20ms);  // t0 + 120: a change restarts the period
  h.set(0x6041, 0, 0x21);
  EXPECT_EQ(h.tick(1), tpdo1(0x21) + "t2B23210000\r");
  EXPECT_EQ(h.run_until(t0 + 170ms), "");
  EXPECT_EQ(h.run_until(t0 + 171ms), tpdo1(0x21));
}

TEST(Sync, TypeOneSendsAtEverySync) {  // PDO-07, SYNC-02, §8 example
  Harness h;
  h.boot();
  h.send(sdo({0x2F, 0x00, 0x18, 0x02, 1}));
  h.send("t00020132");
  h.set(0x6041, 0, 0x27);
  h.tick(1);
  EXPECT_EQ(h.send("t0800"), tpdo1(0x27));
  EXPECT_EQ(h.send("t0800"), tpdo1(0x27));
  EXPECT_EQ(h.send("t08012A"), tpdo1(0x27));  // DLC 1 is a SYNC too (SYNC-07)
  EXPECT_EQ(h.send("t0802AABB"), "");         // DLC 2 is not
  EXPECT_EQ(h.send("r0800"), "");
}

TEST(Sync, TypeThreeEveryThirdSync) {  // PDO-08
  Harness h;
  h.boot();
  h.set(0x1800, 2, 3);
  h.send("t00020132");
  std::string seen;
  for (int i = 1; i <= 9; ++i) seen += h.send("t0800").empty() ? '.' : 'T';
  EXPECT_EQ(seen, "..T..T..T");
  h.send("t00028032");
  h.send("t0800");
  h.send("t00020132");  // counters restart on entering OPERATIONAL
  seen.clear();
  for (int i = 1; i <= 3; ++i) seen += h.send("t0800").empty() ? '.' : 'T';
  EXPECT_EQ(seen, "..T");
}

TEST(Sync, TypeZeroOnlyAfterAChange) {  // PDO-09, SYNC-09
  Harness h;
  h.boot();
  h.set(0x1800, 2, 0);
  h.send("t00020132");
  EXPECT_EQ(h.send("t0800"), tpdo1(0x40));  // none sent since entering OPERATIONAL
  EXPECT_EQ(h.send("t0800"), "");
  h.set(0x6041, 0, 0x21);
  EXPECT_EQ(h.tick(1), "t2B23210000\r");  // TPDO2 is event-driven; TPDO1 waits for the SYNC
  EXPECT_EQ(h.send("t0800"), tpdo1(0x21));
  EXPECT_EQ(h.send("t0800"), "");
}

TEST(Sync, NoEffectOutsideOperational) {  // SYNC-03
  Harness h;
  h.boot();
  h.set(0x1800, 2, 2);
  EXPECT_EQ(h.send("t0800"), "");  // PRE-OPERATIONAL: no counting
  h.send("t00020132");
  EXPECT_EQ(h.send("t0800"), "");
  h.send("t00020232");
  EXPECT_EQ(h.send("t0800"), "");
  h.send("t00020132");
  EXPECT_EQ(h.send("t0800"), "");
  EXPECT_EQ(h.send("t0800"), tpdo1(0x40));
}

TEST(Sync, CobIdRules) {  // SYNC-01, SYNC-04, SYNC-05, SYNC-06
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x40, 0x05, 0x10, 0x00})), resp({0x43, 0x05, 0x10, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x23, 0x05, 0x10, 0x00, 0x80, 0, 0, 0x40})), abort_line(0x1005, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x23, 0x05, 0x10, 0x00, 0x80, 0, 0, 0x20})), abort_line(0x1005, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x23, 0x05, 0x10, 0x00, 0x7F, 0, 0, 0})), abort_line(0x1005, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x23, 0x05, 0x10, 0x00, 0x81, 0, 0, 0})), resp({0x60, 0x05, 0x10, 0x00}));
  h.set(0x1800, 2, 1);
  h.send("t00020132");
  EXPECT_EQ(h.send("t0800"), "");
  EXPECT_EQ(h.send("t0810"), tpdo1(0x40));
}

TEST(Sync, SynchronousRpdoAppliedBeforeTpdoSampling) {  // SYNC-08, PDO-22
  Harness h;
  fake_drive(h);
  h.boot();
  h.set(0x1400, 2, 1);  // RPDO1 synchronous
  h.set(0x1800, 2, 1);  // TPDO1 synchronous
  h.send("t00020132");
  EXPECT_EQ(h.send("t23220600"), "");
  EXPECT_EQ(h.send("t23220700"), "");  // the later frame wins
  EXPECT_EQ(h.number(0x6040, 0), 0);
  EXPECT_EQ(h.send("t0800"), tpdo1(0x23) + "t2B23230000\r");
  EXPECT_EQ(h.number(0x6040, 0), 7);
  EXPECT_EQ(h.send("t0800"), tpdo1(0x23));  // nothing buffered any more
  // leaving OPERATIONAL discards buffered data
  h.send("t23220F00");
  h.send("t00028032");
  h.send("t00020132");
  h.send("t0800");
  EXPECT_EQ(h.number(0x6040, 0), 7);
}

TEST(Pdo, RemoteRequests) {  // PDO-10, PDO-12, PDO-13, §9.5 example
  Harness h;
  h.boot();
  h.send("t00020132");
  h.set(0x6041, 0, 0x0427);
  h.set(0x6064, 0, 30000);
  h.tick(1);
  EXPECT_EQ(h.send("r3B26"), "t3B26270430750000\r");
  EXPECT_EQ(h.send("r3B20"), "t3B26270430750000\r");  // DLC of the RTR ignored
  EXPECT_EQ(h.send("r1B22"), tpdo1(0x0427));          // TPDO1: current data
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80})), resp({0x60, 0x00, 0x18, 0x01}));
  h.send(sdo({0x2B, 0x00, 0x18, 0x03, 0xE8, 0x03}));  // inhibit 100 ms
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00}));
  h.tick(1);
  EXPECT_EQ(h.send("r1B22"), tpdo1(0x0427));  // inhibit does not apply to the reply
  EXPECT_EQ(h.send("r1B22"), tpdo1(0x0427));
  // bit 30: remote requests not allowed
  h.send(sdo({0x23, 0x02, 0x18, 0x01, 0xB2, 0x03, 0x00, 0xC0}));
  h.send(sdo({0x23, 0x02, 0x18, 0x01, 0xB2, 0x03, 0x00, 0x40}));
  EXPECT_EQ(h.send("r3B26"), "");
  EXPECT_EQ(h.send("r4B26"), "t4B26270400000000\r");
}

TEST(Pdo, Type252ReturnsTheSampleOfTheLastSync) {  // PDO-11
  Harness h;
  h.boot();
  h.set(0x1802, 2, 252);
  h.send("t00020132");
  h.set(0x6041, 0, 0x27);
  h.set(0x6064, 0, 100);
  h.tick(1);
  EXPECT_EQ(h.send("r3B26"), "t3B26270064000000\r");  // no SYNC yet: current values
  h.send("t0800");
  h.set(0x6064, 0, 200);
  EXPECT_EQ(h.send("r3B26"), "t3B26270064000000\r");
  h.send("t0800");
  EXPECT_EQ(h.send("r3B26"), "t3B262700C8000000\r");
}

TEST(Pdo, ValidBitAndIdentifierChanges) {  // PDO-14, PDO-15, PDO-16, PDO-17
  Harness h;
  h.boot();
  h.send("t00020132");
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));
  h.set(0x6041, 0, 0x21);
  EXPECT_EQ(h.tick(1), "t2B23210000\r");  // TPDO1 invalid
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x00})),
            resp({0x60, 0x00, 0x18, 0x01}) + tpdo1(0x21));
  // a new identifier while valid is refused; via invalid it works
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xC0, 0x01, 0x00, 0x00})), abort_line(0x1800, 1, 0x06090030));
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xC0, 0x01, 0x00, 0x80}));
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xC0, 0x01, 0x00, 0x00}));
  h.set(0x6041, 0, 0x23);
  EXPECT_EQ(h.tick(1), "t1C022300\rt2B23230000\r");
  // bit 29, bits 11–28
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xC0, 0x01, 0x00, 0xA0})), abort_line(0x1800, 1, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xC0, 0x09, 0x00, 0x80})), abort_line(0x1800, 1, 0x06090030));
  // restricted identifiers while valid; accepted with bit 31
  for (int id : {0x000, 0x07F, 0x101, 0x180, 0x5B2, 0x601, 0x6E0, 0x701, 0x7FF}) {
    h.send(sdo({0x23, 0x01, 0x18, 0x01, 0xB2, 0x02, 0x00, 0x80}));
    EXPECT_EQ(h.send(sdo({0x23, 0x01, 0x18, 0x01, id & 0xFF, id >> 8, 0x00, 0x00})), abort_line(0x1801, 1, 0x06090030))
        << std::hex << id;
    EXPECT_EQ(h.send(sdo({0x23, 0x01, 0x18, 0x01, id & 0xFF, id >> 8, 0x00, 0x80})), resp({0x60, 0x01, 0x18, 0x01}))
        << std::hex << id;
  }
}

TEST(Pdo, TransmissionTypeAndInhibitRules) {  // PDO-18, PDO-19
  Harness h;
  h.boot();
  for (int t : {241, 251}) {
    EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x18, 0x02, t})), abort_line(0x1800, 2, 0x06090030));
  }
  for (int t : {241, 252, 253}) {
    EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x14, 0x02, t})), abort_line(0x1400, 2, 0x06090030));
  }
  for (int t : {0, 240, 252, 253, 254, 255}) {
    EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x18, 0x02, t})), resp({0x60, 0x00, 0x18, 0x02}));
  }
  EXPECT_EQ(h.send(sdo({0x2F, 0x00, 0x14, 0x02, 254})), resp({0x60, 0x00, 0x14, 0x02}));
  EXPECT_EQ(h.send(sdo({0x2B, 0x00, 0x18, 0x03, 10})), abort_line(0x1800, 3, 0x06090030));
  h.send(sdo({0x23, 0x00, 0x18, 0x01, 0xB2, 0x01, 0x00, 0x80}));
  EXPECT_EQ(h.send(sdo({0x2B, 0x00, 0x18, 0x03, 10})), resp({0x60, 0x00, 0x18, 0x03}));
}

TEST(Pdo, Rpdo2WritesControlwordAndMode) {  // PDO-20, PDO-26, §9.8
  Harness h;
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("t33230F0001"), "");
  EXPECT_EQ(h.send("t63284040600000000000"),
            "t5B284B406000"
            "0F000000\r");
  EXPECT_EQ(h.send("t63284060600000000000"), "t5B284F60600001000000\r");
  EXPECT_EQ(h.send("t23220600"), "");  // RPDO1 on MC349 (1400h added)
  EXPECT_EQ(h.number(0x6040, 0), 6);
  EXPECT_EQ(h.send("t43261F0078ECFFFF"), "");
  EXPECT_EQ(h.number(0x607A, 0), -5000);
  EXPECT_EQ(h.send("t53260F00F4010000"), "");
  EXPECT_EQ(h.number(0x60FF, 0), 500);
  // 1400h readable and can be disabled
  EXPECT_EQ(h.send(sdo({0x40, 0x00, 0x14, 0x01})), resp({0x43, 0x00, 0x14, 0x01, 0x32, 0x02}));
  h.send(sdo({0x23, 0x00, 0x14, 0x01, 0x32, 0x02, 0x00, 0x80}));
  h.send("t23220700");
  EXPECT_EQ(h.number(0x6040, 0), 0x0F);
}

TEST(Pdo, ControlwordIsWrittenAfterTheOtherValuesOfThePdo) {  // PDO-27 precondition
  Harness h;
  std::vector<std::int64_t> target_seen_by_controlword;
  h.od->on_write(0x6040, 0, [&](od::WriteRequest&) {
    target_seen_by_controlword.push_back(*h.od->read_number(0x607A, 0));
    return od::AbortCode::none;
  });
  h.boot();
  h.send("t00020132");
  h.send("t43261F0030750000");
  h.send("t43261F0078ECFFFF");
  EXPECT_EQ(target_seen_by_controlword, (std::vector<std::int64_t>{30000, -5000}));
}

TEST(Pdo, RpdosIgnoredOutsideOperational) {  // PDO-21
  Harness h;
  h.boot();
  h.send("t23220F00");
  EXPECT_EQ(h.number(0x6040, 0), 0);
  h.send("t00020232");
  h.send("t23220F00");
  EXPECT_EQ(h.number(0x6040, 0), 0);
  h.send("t00020132");
  h.send("r2322");  // remote frame on an RPDO identifier: ignored
  h.send("T0000023220F00");
  EXPECT_EQ(h.number(0x6040, 0), 0);
}

TEST(Pdo, RpdoLengthErrors) {  // PDO-23, PDO-24, §7.4 "RPDO too short"
  Harness h;
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("t23210F"), "t0B281082110000000000\r");
  EXPECT_EQ(h.number(0x6040, 0), 0);
  EXPECT_EQ(h.send("t23210F"), "");  // once
  EXPECT_EQ(h.send("t23220600"), "t0B280000000000000000\r");
  EXPECT_EQ(h.number(0x6040, 0), 6);
  EXPECT_EQ(h.send("t2323070000"), "t0B282082110000000000\r");  // too long: applied
  EXPECT_EQ(h.number(0x6040, 0), 7);
  EXPECT_EQ(h.send("t2323070000"), "");
  EXPECT_EQ(h.send("t23220700"), "t0B280000000000000000\r");
  h.set(0x1001, 0, 0x05);  // with a fault present, byte 2 adds 0x11 to 1001h
  EXPECT_EQ(h.send("t23210F"), "t0B281082150000000000\r");
  EXPECT_EQ(h.send("t23220600"), "t0B280000050000000000\r");
}

TEST(Pdo, RefusedRpdoValueIsSkippedAndTraced) {  // PDO-25
  std::vector<std::string> trace;
  Node::Hooks hooks;
  hooks.diagnostic = [&](const std::string& t) { trace.push_back(t); };
  Harness h("MC349", {}, false, hooks);
  h.boot();
  h.send("t00020132");
  EXPECT_EQ(h.send("t33230F0063"), "");
  EXPECT_EQ(h.number(0x6040, 0), 0x0F);
  EXPECT_EQ(h.number(0x6060, 0), 0);
  ASSERT_EQ(trace.size(), 1u);
  EXPECT_EQ(trace[0], "RPDO2: write of 6060h.00h refused with 0x06090030");
}

TEST(Pdo, FixedMappingIsReadOnly) {  // PDO-28, §9.7 last row
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t63282F001A0000000000"), "t5B2880001A0002000106\r");
  for (std::uint16_t i : {0x1600, 0x1601, 0x1602, 0x1603, 0x1A00, 0x1A01, 0x1A02, 0x1A03}) {
    EXPECT_EQ(h.send(sdo({0x2F, i & 0xFF, i >> 8, 0, 1})), abort_line(i, 0, 0x06010002));
    EXPECT_EQ(h.send(sdo({0x23, i & 0xFF, i >> 8, 1, 0x10, 0x00, 0x41, 0x60})), abort_line(i, 1, 0x06010002));
    EXPECT_EQ(h.send(sdo({0x23, i & 0xFF, i >> 8, 3, 0x10, 0x00, 0x41, 0x60})), abort_line(i, 3, 0x06090011));
  }
}

}  // namespace
}  // namespace mcemu::canopen::test
