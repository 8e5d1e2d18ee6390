// SDO server: the worked examples of slcan-canopen.md §6.10 byte for byte, and the SDO cases of
// the conformance catalogue §12 (SDO-01 … SDO-14, SDO-27 … SDO-30) at unit level.
#include <gtest/gtest.h>

#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

struct Worked {
  const char* name;
  std::vector<Exchange> steps;
};

class WorkedExample : public ::testing::TestWithParam<Worked> {};

TEST_P(WorkedExample, ByteExact) {
  Harness h;
  h.boot();
  h.set(0x6064, 0, -1234);
  for (const auto& s : GetParam().steps) EXPECT_EQ(h.send(s.request), s.response) << s.request;
}

INSTANTIATE_TEST_SUITE_P(
    Spec, WorkedExample,
    ::testing::Values(Worked{"upload_6041", {{"t63284041600000000000", "t5B284B41600040000000\r"}}},
                      Worked{"upload_1000", {{"t63284000100000000000", "t5B284300100092010200\r"}}},
                      Worked{"upload_1018_01", {{"t63284018100100000000", "t5B28431810013B050000\r"}}},
                      Worked{"upload_6064_negative", {{"t63284064600000000000", "t5B28436460002EFBFFFF\r"}}},
                      Worked{"download_6040", {{"t63282B4060000F000000", "t5B286040600000000000\r"}}},
                      Worked{"download_6060", {{"t63282F60600001000000", "t5B286060600000000000\r"}}},
                      Worked{"download_607A", {{"t6328237A600030750000", "t5B28607A600000000000\r"}}},
                      Worked{"download_6060_unindicated", {{"t63282260600001000000", "t5B286060600000000000\r"}}},
                      Worked{"segmented_upload_1008",
                             {{"t63284008100000000000", "t5B28410810000C000000\r"},
                              {"t63286000000000000000", "t5B28004D433334395F45\r"},
                              {"t63287000000000000000", "t5B281554485F52450000\r"}}},
                      Worked{"segmented_download_607A",
                             {{"t6328217A600004000000", "t5B28607A600000000000\r"},
                              {"t63280730750000000000", "t5B282000000000000000\r"},
                              {"t6328407A600000000000", "t5B28437A600030750000\r"}}},
                      Worked{"block_download_607A_crc",
                             {{"t6328C67A600004000000", "t5B28A47A60007F000000\r"},
                              {"t63288130750000000000", "t5B28A2017F0000000000\r"},
                              {"t6328CD111F0000000000", "t5B28A100000000000000\r"},
                              {"t6328407A600000000000", "t5B28437A600030750000\r"}}},
                      Worked{"block_upload_1008_crc",
                             {{"t6328A40810007F000000", "t5B28C60810000C000000\r"},
                              {"t6328A300000000000000", "t5B28014D433334395F45\rt5B288254485F52450000\r"},
                              {"t6328A2027F0000000000", "t5B28C94DA30000000000\r"},
                              {"t6328A100000000000000", ""}}},
                      Worked{"block_upload_pst", {{"t6328A44160007F040000", "t5B284B41600040000000\r"}}},
                      Worked{"missing_object", {{"t63284000200000000000", "t5B288000200000000206\r"}}},
                      Worked{"write_read_only", {{"t63282B41600000000000", "t5B288041600002000106\r"}}},
                      Worked{"missing_sub", {{"t63284018100500000000", "t5B288018100511000906\r"}}},
                      Worked{"length_too_high", {{"t63282360600001000000", "t5B288060600012000706\r"}}},
                      Worked{"length_too_low", {{"t63282F4060000F000000", "t5B288040600013000706\r"}}},
                      Worked{"invalid_value", {{"t63282F60600063000000", "t5B288060600030000906\r"}}},
                      Worked{"toggle_error",
                             {{"t63284008100000000000", "t5B28410810000C000000\r"},
                              {"t63286000000000000000", "t5B28004D433334395F45\r"},
                              {"t63286000000000000000", "t5B288008100000000305\r"}}},
                      Worked{"invalid_ccs", {{"t6328E000100000000000", "t5B288000100001000405\r"}}},
                      Worked{"segment_while_idle", {{"t63286000000000000000", "t5B288000000001000405\r"}}},
                      Worked{"block_upload_blksize_0", {{"t6328A408100000000000", "t5B288008100002000405\r"}}}),
    [](const ::testing::TestParamInfo<Worked>& i) { return std::string(i.param.name); });

TEST(Sdo, TimeoutAfterExactly1000ms) {  // §6.10 last-but-one row, SDO-13
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t63284008100000000000"), "t5B28410810000C000000\r");
  const Millis t0 = h.now;
  EXPECT_EQ(h.run_until(t0 + 999ms), "");
  EXPECT_EQ(h.run_until(t0 + 1000ms), "t5B288008100000000405\r");
  ASSERT_FALSE(h.log.empty());
  EXPECT_EQ(h.log.back().first, t0 + 1000ms);
  // idle afterwards: a segment request is now out of place
  EXPECT_EQ(h.send("t63286000000000000000"), abort_line(0, 0, 0x05040001));
}

TEST(Sdo, TimeoutRestartsWithEveryServerFrame) {
  Harness h;
  h.boot();
  h.send("t63284008100000000000");
  h.wait(900ms);
  EXPECT_EQ(h.send("t63286000000000000000"), "t5B28004D433334395F45\r");
  EXPECT_EQ(h.wait(999ms), "");
  EXPECT_EQ(h.wait(1ms), "t5B288008100000000405\r");
}

TEST(Sdo, ExpeditedUploadSizes) {  // SDO-01
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x40, 0x61, 0x60, 0x00})), "t5B284F61600000000000\r");  // 1 byte
  EXPECT_EQ(h.send(sdo({0x40, 0x41, 0x60, 0x00})), "t5B284B41600040000000\r");  // 2 bytes
  EXPECT_EQ(h.send(sdo({0x40, 0x18, 0x10, 0x01})), "t5B28431810013B050000\r");  // 4 bytes
  EXPECT_EQ(h.send(sdo({0x40, 0x17, 0x10, 0x00})), "t5B284B17100000000000\r");  // padding is zero
}

TEST(Sdo, ExpeditedDownloadSizesReadBack) {  // SDO-02, SDO-03
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x2F, 0x60, 0x60, 0x00, 0x03})), "t5B286060600000000000\r");
  EXPECT_EQ(h.number(0x6060, 0), 3);
  EXPECT_EQ(h.send(sdo({0x2B, 0x17, 0x10, 0x00, 0xE8, 0x03})), "t5B286017100000000000\r");
  EXPECT_EQ(h.number(0x1017, 0), 1000);
  EXPECT_EQ(h.send(sdo({0x23, 0x7A, 0x60, 0x00, 0x78, 0xEC, 0xFF, 0xFF})), "t5B28607A600000000000\r");
  EXPECT_EQ(h.number(0x607A, 0), -5000);
  // 0x22: size not indicated, the first two bytes are used
  EXPECT_EQ(h.send(sdo({0x22, 0x40, 0x60, 0x00, 0x06, 0x00, 0xAA, 0xBB})), "t5B286040600000000000\r");
  EXPECT_EQ(h.number(0x6040, 0), 6);
  // n ignored when e = s = 1 is not given: 0x26 acts as 0x22
  EXPECT_EQ(h.send(sdo({0x26, 0x40, 0x60, 0x00, 0x07, 0x00, 0xAA, 0xBB})), "t5B286040600000000000\r");
  EXPECT_EQ(h.number(0x6040, 0), 7);
}

TEST(Sdo, SegmentedUpload100A) {  // SDO-05: 15 bytes, 3 segments, last n = 6
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x40, 0x0A, 0x10, 0x00})), "t5B28410A10000F000000\r");
  EXPECT_EQ(h.send(sdo({0x60})), "t5B28007635302E30302E\r");     // "v50.00."
  EXPECT_EQ(h.send(sdo({0x70})), "t5B281031302E30305F52\r");     // "10.00_R"
  EXPECT_EQ(h.send(sdo({0x60})), "t5B280D45000000000000\r");     // "E": t = 0, n = 6, c = 1
  EXPECT_EQ(h.send(sdo({0x70})), abort_line(0, 0, 0x05040001));  // idle afterwards
}

TEST(Sdo, SegmentedDownloadWithoutSize) {  // SDO-07
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x20, 0x7A, 0x60, 0x00})), "t5B28607A600000000000\r");
  EXPECT_EQ(h.send(sdo({0x07, 0x10, 0x27, 0x00, 0x00})), "t5B282000000000000000\r");
  EXPECT_EQ(h.number(0x607A, 0), 10000);
  // five bytes: the segment that exceeds is aborted at once
  h.send(sdo({0x20, 0x7A, 0x60, 0x00}));
  EXPECT_EQ(h.send(sdo({0x05, 1, 2, 3, 4, 5})), abort_line(0x607A, 0, 0x06070012));
  // three bytes: 0x06070010 at the last segment
  h.send(sdo({0x20, 0x7A, 0x60, 0x00}));
  EXPECT_EQ(h.send(sdo({0x09, 1, 2, 3})), abort_line(0x607A, 0, 0x06070010));
  EXPECT_EQ(h.number(0x607A, 0), 10000);
}

TEST(Sdo, SegmentedDownloadAcrossSegmentsAndSizeErrors) {
  Harness h("MC349", {}, true);
  h.boot();
  // 10 bytes into the rw test string: two segments with toggles 0, 1
  EXPECT_EQ(h.send(sdo({0x21, 0x00, 0x2F, 0x00, 10})), "t5B2860002F0000000000\r");
  EXPECT_EQ(h.send(sdo({0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'})), "t5B282000000000000000\r");
  EXPECT_EQ(h.send(sdo({0x19, 'h', 'i', 'j'})), "t5B283000000000000000\r");
  EXPECT_EQ(std::get<std::string>(*h.od->read(0x2F00, 0)), "abcdefghij");
  // indicated 10, delivered 9 → 0x06070013, value unchanged
  h.send(sdo({0x21, 0x00, 0x2F, 0x00, 10}));
  h.send(sdo({0x00, '1', '2', '3', '4', '5', '6', '7'}));
  EXPECT_EQ(h.send(sdo({0x1B, '8', '9'})), abort_line(0x2F00, 0, 0x06070013));
  // indicated 3, delivered 7 → 0x06070012 at once
  h.send(sdo({0x21, 0x00, 0x2F, 0x00, 3}));
  EXPECT_EQ(h.send(sdo({0x00, '1', '2', '3', '4', '5', '6', '7'})), abort_line(0x2F00, 0, 0x06070012));
  EXPECT_EQ(std::get<std::string>(*h.od->read(0x2F00, 0)), "abcdefghij");
  // an empty string uploads segmented: initiate 41 size 0, then 0F
  h.od->write(0x2F00, 0, od::Value{std::string{}}, od::Origin::internal);
  EXPECT_EQ(h.send(sdo({0x40, 0x00, 0x2F, 0x00})), "t5B2841002F0000000000\r");
  EXPECT_EQ(h.send(sdo({0x60})), "t5B280F00000000000000\r");
}

TEST(Sdo, DownloadToggleError) {  // SDO-09
  Harness h("MC349", {}, true);
  h.boot();
  h.send(sdo({0x21, 0x00, 0x2F, 0x00, 10}));
  EXPECT_EQ(h.send(sdo({0x10, 1, 2, 3, 4, 5, 6, 7})), abort_line(0x2F00, 0, 0x05030000));  // first has t=1
  h.send(sdo({0x21, 0x00, 0x2F, 0x00, 10}));
  h.send(sdo({0x00, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(h.send(sdo({0x01, 8, 9, 10})), abort_line(0x2F00, 0, 0x05030000));  // t=0 again
  EXPECT_EQ(std::get<std::string>(*h.od->read(0x2F00, 0)), "");
}

TEST(Sdo, UploadToggleErrorLeavesServerIdle) {  // SDO-08
  Harness h;
  h.boot();
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  EXPECT_EQ(h.send(sdo({0x70})), abort_line(0x1008, 0, 0x05030000));  // first request with t = 1
  EXPECT_EQ(h.send(sdo({0x60})), abort_line(0, 0, 0x05040001));
}

TEST(Sdo, OutOfStateRequests) {  // SDO-10, SDO-11, §6.7
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x00, 1, 2, 3})), abort_line(0, 0, 0x05040001));  // download segment, idle
  EXPECT_EQ(h.send(sdo({0x60, 1, 2, 3})), abort_line(0, 0, 0x05040001));  // upload segment, idle
  EXPECT_EQ(h.send(sdo({0xE0, 0x00, 0x10, 0x00})), abort_line(0x1000, 0, 0x05040001));
  EXPECT_EQ(h.send(sdo({0xFF, 0x41, 0x60, 0x02})), abort_line(0x6041, 2, 0x05040001));
  EXPECT_EQ(h.send(sdo({0xA3, 0x08, 0x10, 0x00})), abort_line(0x1008, 0, 0x05040001));  // block start, idle
  EXPECT_EQ(h.send(sdo({0xA2, 0x08, 0x10, 0x00})), abort_line(0x1008, 0, 0x05040001));
  EXPECT_EQ(h.send(sdo({0xA1, 0x08, 0x10, 0x00})), abort_line(0x1008, 0, 0x05040001));
  EXPECT_EQ(h.send(sdo({0xC1, 0x08, 0x10, 0x00})), abort_line(0x1008, 0, 0x05040001));
  // ccs 7 during a transfer names the transfer
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  EXPECT_EQ(h.send(sdo({0xE0, 0x00, 0x60, 0x00})), abort_line(0x1008, 0, 0x05040001));
  // wrong kind during a segmented upload / download
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  EXPECT_EQ(h.send(sdo({0x00, 1})), abort_line(0x1008, 0, 0x05040001));
  h.send(sdo({0x21, 0x7A, 0x60, 0x00, 4}));
  EXPECT_EQ(h.send(sdo({0x60})), abort_line(0x607A, 0, 0x05040001));
}

TEST(Sdo, ClientAbortSilencesAndNextRequestIsServed) {  // SDO-12
  Harness h;
  h.boot();
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  EXPECT_EQ(h.send("t63288000000000000405\r"), "");  // python-canopen's abort, index 0000h
  EXPECT_EQ(h.wait(2000ms), "");                     // no timeout either
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  EXPECT_EQ(h.send("t63289F41600000000000"), "");  // any 0x80…0x9F is an abort
}

TEST(Sdo, NewInitiateDropsTheOldTransfer) {  // SDO-14
  Harness h;
  h.boot();
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  EXPECT_EQ(h.send(sdo({0x40, 0x08, 0x10, 0x00})), "t5B28410810000C000000\r");
  EXPECT_EQ(h.send(sdo({0x60})), "t5B28004D433334395F45\r");
  EXPECT_EQ(h.wait(5000ms).find("t5B288008"), 0u);  // only the timeout of the second transfer
}

TEST(Sdo, LengthAndAccessAndValueErrors) {  // SDO-27, SDO-28, SDO-29
  Harness h("MC349", {}, true);
  h.boot();
  EXPECT_EQ(h.send(sdo({0x23, 0x40, 0x60, 0x00, 0x0F})), abort_line(0x6040, 0, 0x06070012));
  EXPECT_EQ(h.send(sdo({0x2F, 0x40, 0x60, 0x00, 0x0F})), abort_line(0x6040, 0, 0x06070013));
  EXPECT_EQ(h.send(sdo({0x21, 0x40, 0x60, 0x00, 4})), abort_line(0x6040, 0, 0x06070012));  // segmented initiate
  EXPECT_EQ(h.send(sdo({0x21, 0x40, 0x60, 0x00, 1})), abort_line(0x6040, 0, 0x06070013));
  EXPECT_EQ(h.send(sdo({0x2B, 0x41, 0x60, 0x00})), abort_line(0x6041, 0, 0x06010002));
  EXPECT_EQ(h.send(sdo({0x40, 0x00, 0x20, 0x00})), abort_line(0x2000, 0, 0x06020000));
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x20, 0x00})), abort_line(0x2000, 0, 0x06020000));
  EXPECT_EQ(h.send(sdo({0x40, 0x18, 0x10, 0x05})), abort_line(0x1018, 5, 0x06090011));
  EXPECT_EQ(h.send(sdo({0x40, 0x41, 0x60, 0x01})), abort_line(0x6041, 1, 0x06090011));  // VAR sub 1 (OD-06)
  EXPECT_EQ(h.send(sdo({0x40, 0x01, 0x2F, 0x00})), abort_line(0x2F01, 0, 0x06010001));  // write-only
  EXPECT_EQ(h.send(sdo({0xA4, 0x01, 0x2F, 0x00, 127})), abort_line(0x2F01, 0, 0x06010001));
  EXPECT_EQ(h.send(sdo({0x2F, 0x60, 0x60, 0x00, 99})), abort_line(0x6060, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x2F, 0x04, 0x34, 0x03, 0})), abort_line(0x3404, 3, 0x06090032));
  EXPECT_EQ(h.send(sdo({0x2F, 0x04, 0x34, 0x03, 128})), abort_line(0x3404, 3, 0x06090031));
  EXPECT_EQ(h.send(sdo({0x2B, 0x03, 0x10, 0x00, 1})), abort_line(0x1003, 0, 0x06070012));
  EXPECT_EQ(h.send(sdo({0x2F, 0x03, 0x10, 0x00, 1})), abort_line(0x1003, 0, 0x06090030));
  EXPECT_EQ(h.send(sdo({0x2F, 0x03, 0x10, 0x00, 0})), "t5B286003100000000000\r");
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x12, 0x01, 0x32, 0x06, 0, 0})), abort_line(0x1200, 1, 0x06010002));  // OTH-08
  EXPECT_EQ(h.send(sdo({0x23, 0x00, 0x12, 0x02, 0xB2, 0x05, 0, 0})), abort_line(0x1200, 2, 0x06010002));
  EXPECT_EQ(h.send(sdo({0x2F, 0x10, 0x10, 0x00, 3})), abort_line(0x1010, 0, 0x06010002));  // OTH-06
  EXPECT_EQ(h.send(sdo({0x23, 0x10, 0x10, 0x04})), abort_line(0x1010, 4, 0x06090011));
  EXPECT_EQ(h.send(sdo({0x40, 0x16, 0x10, 0x00})), abort_line(0x1016, 0, 0x06020000));  // HB-07
  for (std::uint16_t i : {0x1006, 0x1007, 0x1019}) {                                    // SYNC-10
    EXPECT_EQ(h.send(sdo({0x40, i & 0xFF, i >> 8, 0x00})), abort_line(i, 0, 0x06020000));
  }
}

TEST(Sdo, StoppedGivesNoAnswerAndDlc7IsIgnored) {  // SDO-30
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t632740416000000000"), "");  // DLC 7
  EXPECT_EQ(h.send("t00020232"), "");            // stop
  EXPECT_EQ(h.send("t63284041600000000000"), "");
  EXPECT_EQ(h.send("t63288000000000000405"), "");
  EXPECT_EQ(h.send("t00028032"), "");  // pre-operational
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
  EXPECT_EQ(h.send("t632740416000000000"), "");
  h.send("t00020132");
  EXPECT_EQ(h.send("t632740416000000000"), "");
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");
}

TEST(Sdo, StoppedEndsARunningTransferSilently) {
  Harness h;
  h.boot();
  h.send(sdo({0x40, 0x08, 0x10, 0x00}));
  h.send("t00020232");
  EXPECT_EQ(h.wait(3000ms), "");
}

TEST(Sdo, HookFailuresAreGeneralErrors) {  // §6.9 0x08000000
  Harness h("MC349", {}, true);
  h.od->on_write(0x2F03, 0, [](od::WriteRequest&) { return od::AbortCode::general; });
  h.od->on_read(0x2F03, 0, [](const od::EntryInfo&) -> od::Result<od::Value> { return od::AbortCode::general; });
  h.boot();
  EXPECT_EQ(h.send(sdo({0x2F, 0x03, 0x2F, 0x00, 1})), abort_line(0x2F03, 0, 0x08000000));
  EXPECT_EQ(h.send(sdo({0x40, 0x03, 0x2F, 0x00})), abort_line(0x2F03, 0, 0x08000000));
  EXPECT_EQ(h.send(sdo({0xA4, 0x03, 0x2F, 0x00, 127})), abort_line(0x2F03, 0, 0x08000000));
}

TEST(Sdo, LengthTolerantEntryAcceptsFourBytes) {
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0x23, 0x11, 0x35, 0x05, 0x10, 0x27, 0, 0})), "t5B286011350500000000\r");
  EXPECT_EQ(h.number(0x3511, 5), 10000);
  EXPECT_EQ(h.send(sdo({0x23, 0x11, 0x35, 0x05, 0x00, 0x00, 0x01, 0})), abort_line(0x3511, 5, 0x06090031));
}

}  // namespace
}  // namespace mcemu::canopen::test
