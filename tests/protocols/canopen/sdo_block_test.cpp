// SDO block transfers (slcan-canopen.md §6.4–§6.6; conformance SDO-15 … SDO-26), driven by a small
// block client written against CiA 301 in this file, on the extended test dictionary.
#include <gtest/gtest.h>

#include <random>

#include "protocols/canopen/crc16.hpp"
#include "tests/protocols/canopen/harness.hpp"

namespace mcemu::canopen::test {
namespace {

can::Frame request(std::initializer_list<int> bytes) {
  can::Frame f;
  f.id = 0x632;
  f.dlc = 8;
  std::size_t i = 0;
  for (int b : bytes) f.data[i++] = static_cast<std::uint8_t>(b);
  return f;
}

can::Frame request(const std::array<std::uint8_t, 8>& bytes) {
  can::Frame f;
  f.id = 0x632;
  f.dlc = 8;
  f.data = bytes;
  return f;
}

struct BlockClient {
  Harness& h;
  std::vector<can::Frame> send(const can::Frame& f) { return h.node->on_frame(f, h.now); }

  // Block download of `data`; returns the final server frame (A1 or an abort).
  can::Frame download(std::uint16_t index, std::uint8_t sub, const std::vector<std::uint8_t>& data, bool crc = true,
                      bool size = true, std::size_t* sub_blocks = nullptr) {
    std::array<std::uint8_t, 8> init{};
    init[0] = static_cast<std::uint8_t>(0xC0 | (crc ? 0x04 : 0) | (size ? 0x02 : 0));
    init[1] = index & 0xFF;
    init[2] = index >> 8;
    init[3] = sub;
    for (int i = 0; i < 4; ++i) init[4 + i] = static_cast<std::uint8_t>(data.size() >> (8 * i));
    auto r = send(request(init));
    EXPECT_EQ(r.size(), 1u);
    if (r[0].data[0] == 0x80) return r[0];
    EXPECT_EQ(r[0].data[0], crc ? 0xA4 : 0xA0);
    int blksize = r[0].data[4];
    std::size_t pos = 0;
    std::size_t blocks = 0;
    bool done = false;
    while (!done) {
      ++blocks;
      can::Frame ack;
      for (int seq = 1; seq <= blksize; ++seq) {
        std::array<std::uint8_t, 8> seg{};
        const std::size_t chunk = std::min<std::size_t>(7, data.size() - pos);
        const bool last = pos + chunk >= data.size();
        seg[0] = static_cast<std::uint8_t>((last ? 0x80 : 0) | seq);
        std::copy_n(data.begin() + static_cast<std::ptrdiff_t>(pos), chunk, seg.begin() + 1);
        pos += chunk;
        auto out = send(request(seg));
        if (!out.empty()) {
          EXPECT_EQ(out.size(), 1u);
          ack = out[0];
          if (ack.data[0] == 0x80) return ack;
          EXPECT_EQ(ack.data[0], 0xA2);
          EXPECT_EQ(ack.data[1], seq);
          done = last;
          break;
        }
        if (last) ADD_FAILURE() << "no A2 after the last segment";
      }
      blksize = ack.data[2];
    }
    if (sub_blocks) *sub_blocks = blocks;
    const std::size_t n = data.empty() ? 7 : (7 - data.size() % 7) % 7;
    const std::uint16_t c = crc16_ccitt(data);
    auto end = send(request({0xC1 | static_cast<int>(n << 2), c & 0xFF, c >> 8}));
    EXPECT_EQ(end.size(), 1u);
    return end.empty() ? can::Frame{} : end[0];
  }

  // Block upload; returns the data (and checks the CRC when asked for).
  std::vector<std::uint8_t> upload(std::uint16_t index, std::uint8_t sub, int blksize, bool crc = true) {
    auto r = send(request({crc ? 0xA4 : 0xA0, index & 0xFF, index >> 8, sub, blksize, 0}));
    EXPECT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].data[0], crc ? 0xC6 : 0xC2);
    const std::uint32_t size = r[0].data[4] | (r[0].data[5] << 8) | (r[0].data[6] << 16);
    std::vector<std::uint8_t> data;
    auto segs = send(request({0xA3}));
    for (;;) {
      bool last = false;
      int seqs = 0;
      for (const auto& s : segs) {
        EXPECT_EQ(s.data[0] & 0x7F, ++seqs);
        data.insert(data.end(), s.data.begin() + 1, s.data.end());
        last = (s.data[0] & 0x80) != 0;
      }
      EXPECT_TRUE(last || seqs == blksize);
      segs = send(request({0xA2, seqs, blksize}));
      if (last) break;
    }
    EXPECT_EQ(segs.size(), 1u);
    const std::size_t n = (segs[0].data[0] >> 2) & 7;
    EXPECT_EQ(segs[0].data[0] & 0xE3, 0xC1);
    data.resize(data.size() - n);
    EXPECT_EQ(data.size(), size);
    const std::uint16_t got = segs[0].data[1] | (segs[0].data[2] << 8);
    EXPECT_EQ(got, crc ? crc16_ccitt(data) : 0);
    EXPECT_TRUE(send(request({0xA1})).empty());
    return data;
  }
};

std::vector<std::uint8_t> random_bytes(std::size_t n) {
  std::mt19937 rng(12345);
  std::vector<std::uint8_t> v(n);
  for (auto& b : v) b = static_cast<std::uint8_t>(0x20 + rng() % 95);
  return v;
}

TEST(SdoBlock, UploadWithoutCrc) {  // SDO-16: no CRC bit in the answer, end frame bytes 1–2 are 0
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t6328A00810007F000000"), "t5B28C20810000C000000\r");
  EXPECT_EQ(h.send("t6328A300000000000000"), "t5B28014D433334395F45\rt5B288254485F52450000\r");
  EXPECT_EQ(h.send("t6328A2027F0000000000"), "t5B28C900000000000000\r");
  EXPECT_EQ(h.send("t6328A100000000000000"), "");
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");  // idle again
}

TEST(SdoBlock, UploadBlksizeOneOf1000Bytes) {  // SDO-17
  Harness h("MC349", {}, true);
  h.boot();
  BlockClient c{h};
  const auto data = c.upload(0x2F02, 0, 1);
  const std::string want = std::get<std::string>(*h.od->read(0x2F02, 0));
  EXPECT_EQ(std::string(data.begin(), data.end()), want);
}

TEST(SdoBlock, UploadSeveralSubBlocksWithAndWithoutCrc) {
  Harness h("MC349", {}, true);
  h.boot();
  BlockClient c{h};
  const std::string want = std::get<std::string>(*h.od->read(0x2F02, 0));
  for (int blk : {5, 127}) {
    for (bool crc : {true, false}) {
      const auto data = c.upload(0x2F02, 0, blk, crc);
      EXPECT_EQ(std::string(data.begin(), data.end()), want) << blk << " " << crc;
    }
  }
}

TEST(SdoBlock, UploadProtocolSwitch) {  // SDO-18
  Harness h;
  h.boot();
  EXPECT_EQ(h.send("t6328A40810007F0C0000"), "t5B28410810000C000000\r");  // pst 12 ≥ 12 bytes
  EXPECT_EQ(h.send("t63286000000000000000"), "t5B28004D433334395F45\r");
  EXPECT_EQ(h.send("t63287000000000000000"), "t5B281554485F52450000\r");
  EXPECT_EQ(h.send("t6328A40810007F0B0000"), "t5B28C60810000C000000\r");  // pst 11 < 12: block
}

TEST(SdoBlock, UploadAckBelowSentResends) {  // SDO-19
  Harness h("MC349", {}, true);
  h.boot();
  const std::string want = std::get<std::string>(*h.od->read(0x2F02, 0));
  const auto b = [&](std::size_t i) { return static_cast<int>(static_cast<unsigned char>(want[i])); };
  h.send(sdo({0xA4, 0x02, 0x2F, 0x00, 4}));  // blksize 4
  const std::string first = h.send(sdo({0xA3}));
  ASSERT_EQ(first.size(), 4u * 22u);
  EXPECT_EQ(first.substr(0, 22), resp({0x01, b(0), b(1), b(2), b(3), b(4), b(5), b(6)}));
  // ack 2: the next sub-block restarts with byte 14, numbered from 1
  const std::string again = h.send(sdo({0xA2, 2, 4}));
  ASSERT_EQ(again.size(), 4u * 22u);
  EXPECT_EQ(again.substr(0, 22), resp({0x01, b(14), b(15), b(16), b(17), b(18), b(19), b(20)}));
  EXPECT_EQ(again.substr(66, 22), resp({0x04, b(35), b(36), b(37), b(38), b(39), b(40), b(41)}));
  // ack 0 resends the whole sub-block; ack above what was sent → 0x05040003
  EXPECT_EQ(h.send(sdo({0xA2, 0, 4})), again);
  EXPECT_EQ(h.send(sdo({0xA2, 5, 4})), abort_line(0x2F02, 0, 0x05040003));
}

TEST(SdoBlock, UploadBlockSizeErrors) {  // SDO-20
  Harness h;
  h.boot();
  EXPECT_EQ(h.send(sdo({0xA4, 0x08, 0x10, 0x00, 0})), abort_line(0x1008, 0, 0x05040002));
  EXPECT_EQ(h.send(sdo({0xA4, 0x08, 0x10, 0x00, 128})), abort_line(0x1008, 0, 0x05040002));
  EXPECT_EQ(h.send(sdo({0xA4, 0x08, 0x10, 0x00, 1})), "t5B28C60810000C000000\r");
  h.send(sdo({0xA3}));
  EXPECT_EQ(h.send(sdo({0xA2, 1, 0})), abort_line(0x1008, 0, 0x05040002));  // blk 0 in the ack
  h.send(sdo({0xA4, 0x08, 0x10, 0x00, 1}));
  h.send(sdo({0xA3}));
  EXPECT_EQ(h.send(sdo({0xA2, 1, 128})), abort_line(0x1008, 0, 0x05040002));
  h.send(sdo({0xA4, 0x08, 0x10, 0x00, 1}));
  EXPECT_EQ(h.send(sdo({0xA2, 1, 1})), abort_line(0x1008, 0, 0x05040001));  // ack before start
  h.send(sdo({0xA4, 0x08, 0x10, 0x00, 1}));
  h.send(sdo({0xA3}));
  EXPECT_EQ(h.send(sdo({0xA1})), abort_line(0x1008, 0, 0x05040001));  // end response too early
  h.send(sdo({0xA4, 0x08, 0x10, 0x00, 1}));
  h.send(sdo({0xA3}));
  EXPECT_EQ(h.send(sdo({0xA3})), abort_line(0x1008, 0, 0x05040001));  // start twice
}

TEST(SdoBlock, UploadTimesOutWaitingForAck) {
  Harness h;
  h.boot();
  h.send(sdo({0xA4, 0x08, 0x10, 0x00, 127}));
  h.send(sdo({0xA3}));
  EXPECT_EQ(h.wait(999ms), "");
  EXPECT_EQ(h.wait(1ms), abort_line(0x1008, 0, 0x05040000));
}

TEST(SdoBlock, EmptyObjectUpload) {  // §6.5 last paragraph
  Harness h("MC349", {}, true);
  h.boot();
  EXPECT_EQ(h.send("t6328A4002F007F000000"), "t5B28C6002F0000000000\r");
  EXPECT_EQ(h.send("t6328A300000000000000"), "t5B288100000000000000\r");
  EXPECT_EQ(h.send("t6328A2017F0000000000"), "t5B28DD00000000000000\r");
  EXPECT_EQ(h.send("t6328A100000000000000"), "");
}

TEST(SdoBlock, Download100kBOverSeveralSubBlocksAndBack) {  // SDO-22
  Harness h("MC349", {}, true);
  h.boot();
  BlockClient c{h};
  const auto data = random_bytes(100 * 1024);
  std::size_t blocks = 0;
  const auto end = c.download(0x2F00, 0, data, true, true, &blocks);
  EXPECT_EQ(end.data[0], 0xA1);
  EXPECT_EQ(blocks, (data.size() + 7 * 127 - 1) / (7 * 127));
  const std::string stored = std::get<std::string>(*h.od->read(0x2F00, 0));
  EXPECT_EQ(stored, std::string(data.begin(), data.end()));
  const auto back = c.upload(0x2F00, 0, 127, true);
  EXPECT_EQ(back, data);
  EXPECT_EQ(crc16_ccitt(back), crc16_ccitt(data));
  // the same without CRC and without size
  const auto other = random_bytes(7 * 127 * 2 + 3);
  EXPECT_EQ(c.download(0x2F00, 0, other, false, false).data[0], 0xA1);
  EXPECT_EQ(c.upload(0x2F00, 0, 33, false), other);
}

TEST(SdoBlock, DownloadWrongCrc) {  // SDO-23
  Harness h;
  h.boot();
  h.send("t6328C67A600004000000");
  EXPECT_EQ(h.send("t63288130750000000000"), "t5B28A2017F0000000000\r");
  EXPECT_EQ(h.send("t6328CD121F0000000000"), abort_line(0x607A, 0, 0x05040004));
  EXPECT_EQ(h.number(0x607A, 0), 0);
  // without CRC the end frame's CRC bytes are ignored
  EXPECT_EQ(h.send("t6328C27A600004000000"), "t5B28A07A60007F000000\r");
  h.send("t63288130750000000000");
  EXPECT_EQ(h.send("t6328CDFFFF0000000000"), "t5B28A100000000000000\r");
  EXPECT_EQ(h.number(0x607A, 0), 30000);
}

TEST(SdoBlock, DownloadSequenceErrorsAndResend) {  // SDO-24
  Harness h("MC349", {}, true);
  h.boot();
  h.send(sdo({0xC6, 0x00, 0x2F, 0x00}));
  EXPECT_EQ(h.send(sdo({0x00, 1, 2})), abort_line(0x2F00, 0, 0x05040003));  // sequence 0
  h.send(sdo({0xC6, 0x00, 0x2F, 0x00}));
  EXPECT_EQ(h.send(sdo({0x80, 1, 2})), "");  // 0x80 in a sub-block: client abort, silent
  EXPECT_EQ(h.wait(2000ms), "");
  // a server announcing blksize 3: sequence 4 is beyond it
  Harness s("MC349", CanopenConfig{.sdo_block_size = 3}, true);
  s.boot();
  EXPECT_EQ(s.send(sdo({0xC6, 0x00, 0x2F, 0x00})), resp({0xA4, 0x00, 0x2F, 0x00, 3}));
  EXPECT_EQ(s.send(sdo({0x04, 1, 2})), abort_line(0x2F00, 0, 0x05040003));
  EXPECT_EQ(s.send(sdo({0xC6, 0x00, 0x2F, 0x00})), resp({0xA4, 0x00, 0x2F, 0x00, 3}));
  EXPECT_EQ(s.send(sdo({0xFF, 1, 2})), abort_line(0x2F00, 0, 0x05040003));  // 127 with c = 1
  // out of order: 1, 3 (ignored), 2 (ignored after the gap) with c = 1 → A2 ack 1; resend from 2
  s.send(sdo({0xC0, 0x00, 0x2F, 0x00}));  // no CRC, no size
  EXPECT_EQ(s.send(sdo({0x01, 'a', 'b', 'c', 'd', 'e', 'f', 'g'})), "");
  EXPECT_EQ(s.send(sdo({0x03, 'x', 'x', 'x', 'x', 'x', 'x', 'x'})), resp({0xA2, 1, 3}));  // 3 = blksize ends it
  EXPECT_EQ(s.send(sdo({0x01, 'h', 'i', 'j', 'k', 'l', 'm', 'n'})), "");
  EXPECT_EQ(s.send(sdo({0x01, 'h', 'i', 'j', 'k', 'l', 'm', 'n'})), "");  // duplicate: ignored
  EXPECT_EQ(s.send(sdo({0x82, 'o', 'p'})), resp({0xA2, 1, 3}));           // c = 1 ends the sub-block
  EXPECT_EQ(s.send(sdo({0x81, 'o', 'p'})), resp({0xA2, 1, 3}));           // resend, in order now
  EXPECT_EQ(s.send(sdo({0xC1 | (5 << 2)})), resp({0xA1}));
  EXPECT_EQ(std::get<std::string>(*s.od->read(0x2F00, 0)), "abcdefghijklmnop");
}

TEST(SdoBlock, DownloadSizeErrors) {  // SDO-25 and the size rules of §6.4
  Harness h("MC349", {}, true);
  h.boot();
  // indicated 4, five data bytes → 0x06070012 at the end; three → 0x06070013
  h.send(sdo({0xC6, 0x7A, 0x60, 0x00, 4}));
  EXPECT_EQ(h.send(sdo({0x81, 1, 2, 3, 4, 5})), resp({0xA2, 1, 127}));
  const std::uint16_t c5 = crc16_ccitt(std::vector<std::uint8_t>{1, 2, 3, 4, 5});
  EXPECT_EQ(h.send(sdo({0xC1 | (2 << 2), c5 & 0xFF, c5 >> 8})), abort_line(0x607A, 0, 0x06070012));
  h.send(sdo({0xC6, 0x7A, 0x60, 0x00, 4}));
  h.send(sdo({0x81, 1, 2, 3}));
  const std::uint16_t c3 = crc16_ccitt(std::vector<std::uint8_t>{1, 2, 3});
  EXPECT_EQ(h.send(sdo({0xC1 | (4 << 2), c3 & 0xFF, c3 >> 8})), abort_line(0x607A, 0, 0x06070013));
  EXPECT_EQ(h.number(0x607A, 0), 0);
  // indicated 4: a second segment can only carry excess bytes → 0x06070012 at once
  h.send(sdo({0xC6, 0x7A, 0x60, 0x00, 4}));
  EXPECT_EQ(h.send(sdo({0x01, 1, 2, 3, 4})), "");
  EXPECT_EQ(h.send(sdo({0x02, 5})), abort_line(0x607A, 0, 0x06070012));
  // no size, numeric entry: excess at once, wrong total → 0x06070010
  h.send(sdo({0xC4, 0x7A, 0x60, 0x00}));
  h.send(sdo({0x01, 1, 2, 3, 4}));
  EXPECT_EQ(h.send(sdo({0x02, 5})), abort_line(0x607A, 0, 0x06070012));
  h.send(sdo({0xC0, 0x7A, 0x60, 0x00}));
  EXPECT_EQ(h.send(sdo({0x81, 1, 2})), resp({0xA2, 1, 127}));
  EXPECT_EQ(h.send(sdo({0xC1 | (5 << 2)})), abort_line(0x607A, 0, 0x06070010));
  h.send(sdo({0xC0, 0x7A, 0x60, 0x00}));
  h.send(sdo({0x81, 0x10, 0x27, 0, 0}));
  EXPECT_EQ(h.send(sdo({0xC1 | (3 << 2)})), resp({0xA1}));
  EXPECT_EQ(h.number(0x607A, 0), 10000);
  // initiate checks 1–4
  EXPECT_EQ(h.send(sdo({0xC6, 0x41, 0x60, 0x00, 2})), abort_line(0x6041, 0, 0x06010002));
  EXPECT_EQ(h.send(sdo({0xC6, 0x7A, 0x60, 0x00, 5})), abort_line(0x607A, 0, 0x06070012));
  EXPECT_EQ(h.send(sdo({0xC6, 0x7A, 0x60, 0x00, 2})), abort_line(0x607A, 0, 0x06070013));
  EXPECT_EQ(h.send(sdo({0xC6, 0x00, 0x20, 0x00, 2})), abort_line(0x2000, 0, 0x06020000));
  // an empty string: one segment 0x81, end with n = 7
  h.od->write(0x2F00, 0, od::Value{std::string("old")}, od::Origin::internal);
  EXPECT_EQ(h.send(sdo({0xC6, 0x00, 0x2F, 0x00, 0})), resp({0xA4, 0x00, 0x2F, 0x00, 127}));
  EXPECT_EQ(h.send(sdo({0x81})), resp({0xA2, 1, 127}));
  EXPECT_EQ(h.send(sdo({0xDD})), resp({0xA1}));
  EXPECT_EQ(std::get<std::string>(*h.od->read(0x2F00, 0)), "");
}

TEST(SdoBlock, DownloadOnlyEndFrameAfterLastSegment) {
  Harness h;
  h.boot();
  h.send("t6328C67A600004000000");
  h.send("t63288130750000000000");
  EXPECT_EQ(h.send(sdo({0xA3})), abort_line(0x607A, 0, 0x05040001));
  h.send("t6328C67A600004000000");
  h.send("t63288130750000000000");
  EXPECT_EQ(h.send("t63284041600000000000"), "t5B284B41600040000000\r");  // a new initiate is served
}

TEST(SdoBlock, DownloadStallTimesOut) {  // SDO-26
  Harness h("MC349", {}, true);
  h.boot();
  h.send(sdo({0xC6, 0x00, 0x2F, 0x00, 100}));
  h.wait(500ms);
  EXPECT_EQ(h.send(sdo({0x01, 1, 2, 3, 4, 5, 6, 7})), "");
  EXPECT_EQ(h.wait(999ms), "");  // measured from the client's last segment
  EXPECT_EQ(h.wait(1ms), abort_line(0x2F00, 0, 0x05040000));
}

}  // namespace
}  // namespace mcemu::canopen::test
