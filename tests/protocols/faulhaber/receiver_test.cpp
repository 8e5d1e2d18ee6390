// The receiver of faulhaber.md §4: every case fed whole, split at every byte offset and byte by
// byte gives the same frames and the same drops; garbage, stray `S`, wrong `E`, wrong CRC with the
// check on and off, L < 4, the 50 ms inter-byte timeout, frames with 0x53/0x45 inside, L = 255.
#include "protocols/faulhaber/receiver.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "protocols/faulhaber/crc.hpp"
#include "protocols/faulhaber/describe.hpp"
#include "tests/protocols/faulhaber/test_dictionary.hpp"

namespace mcemu::faulhaber {
namespace {

using namespace std::chrono_literals;
using test::bytes;

struct Recorder final : Receiver::Sink {
  bool crc = true;
  std::vector<std::string> frames;  // wire bytes as hex
  std::vector<std::string> drops;   // "reason: hex", garbage excepted
  std::size_t garbage = 0;
  std::function<void(const FrameView&)> on;

  void on_frame(const FrameView& f, std::span<const std::uint8_t> raw) override {
    frames.push_back(hex(raw));
    if (on) on(f);
  }
  void on_dropped(const Dropped& d) override {
    if (d.reason == DropReason::garbage) {
      garbage += d.count;
      EXPECT_LE(d.bytes.size(), Receiver::k_garbage_kept);
      return;
    }
    EXPECT_EQ(d.bytes.size(), d.count);
    drops.push_back(std::string(to_string(d.reason)) + ": " + hex(d.bytes));
  }
  bool check_crc() override { return crc; }
};

struct Case {
  const char* name;
  std::string input;
  bool crc;
  std::vector<std::string> frames;
  std::vector<std::string> drops;
  std::size_t garbage;
};

const std::string k_read = "53 07 01 01 41 60 00 73 45 ";
const std::string k_write = "53 09 01 02 40 60 00 06 00 2C 45 ";

std::vector<Case> cases() {
  std::vector<Case> v = {
      {"one frame", k_read, true, {"53 07 01 01 41 60 00 73 45"}, {}, 0},
      {"two frames", k_read + k_write, true, {"53 07 01 01 41 60 00 73 45", "53 09 01 02 40 60 00 06 00 2C 45"}, {}, 0},
      {"garbage before SOF", "00 11 FF 0D 0A 45 " + k_read, true, {"53 07 01 01 41 60 00 73 45"}, {}, 6},
      {"garbage between frames",
       k_read + "0D 0A " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45", "53 07 01 01 41 60 00 73 45"},
       {},
       2},
      {"stray S then L < 4", "53 00 " + k_read, true, {"53 07 01 01 41 60 00 73 45"}, {"L < 4: 53 00"}, 0},
      {"stray S then a short L",
       "53 05 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"no E: 53 05 53 07 01 01 41"},
       0},
      {"wrong E then a good frame",
       "53 07 01 01 41 60 00 73 46 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"no E: 53 07 01 01 41 60 00 73 46"},
       0},
      {"wrong E hides a frame after its S",
       "53 08 01 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"no E: 53 08 01 53 07 01 01 41 60 00"},
       0},
      {"wrong CRC hides a frame after its S",
       "53 0A 01 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"bad CRC: 53 0A 01 53 07 01 01 41 60 00 73 45"},
       0},
      {"wrong CRC, check on",
       "53 07 01 01 41 60 00 74 45 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"bad CRC: 53 07 01 01 41 60 00 74 45"},
       0},
      {"wrong CRC, check off",
       "53 07 01 01 41 60 00 74 45 " + k_read,
       false,
       {"53 07 01 01 41 60 00 74 45", "53 07 01 01 41 60 00 73 45"},
       {},
       0},
      {"L < 4", "53 03 01 00 50 45 " + k_read, true, {"53 07 01 01 41 60 00 73 45"}, {"L < 4: 53 03"}, 4},
      {"L = 0",
       "53 00 53 01 53 02 53 03 " + k_read,
       true,
       {"53 07 01 01 41 60 00 73 45"},
       {"L < 4: 53 00", "L < 4: 53 01", "L < 4: 53 02", "L < 4: 53 03"},
       0},
      {"CRC is 0x53",
       "53 0B 01 01 64 60 00 09 00 00 00 53 45 " + k_read,
       true,
       {"53 0B 01 01 64 60 00 09 00 00 00 53 45", "53 07 01 01 41 60 00 73 45"},
       {},
       0},
      {"E and S in the data",
       "53 13 01 00 4D 43 53 20 33 32 34 32 20 42 58 34 20 45 54 A8 45",
       true,
       {"53 13 01 00 4D 43 53 20 33 32 34 32 20 42 58 34 20 45 54 A8 45"},
       {},
       0},
      {"value 0x45 0x53",
       "53 0B 01 02 FF 60 00 45 53 45 53 F8 45",
       false,
       {"53 0B 01 02 FF 60 00 45 53 45 53 F8 45"},
       {},
       0},
      {"an incomplete frame at the end", k_read + "53 07 01 01", true, {"53 07 01 01 41 60 00 73 45"}, {}, 0},
  };
  // A stray S swallows what follows until its L + 2 bytes are in; the missing E then sends the
  // scan back to the byte after it, and every frame behind it comes out.
  std::string ten;
  for (int i = 0; i < 10; ++i) ten += k_read;
  Case stray{"stray S before ten frames", "53 " + ten, true, {}, {}, 0};
  for (int i = 0; i < 10; ++i) stray.frames.push_back("53 07 01 01 41 60 00 73 45");
  const auto all = bytes(stray.input);
  stray.drops.push_back("no E: " + hex(std::span(all).first(0x53 + 2)));
  v.push_back(stray);
  // L = 255: the longest frame.
  Frame longest{1, 0x42, std::vector<std::uint8_t>(k_max_data, 0x53)};
  v.push_back({"L = 255", hex(encode(longest)), true, {hex(encode(longest))}, {}, 0});
  return v;
}

Recorder run(const Case& c, const std::vector<std::size_t>& cuts) {
  const auto b = bytes(c.input);
  Recorder r;
  r.crc = c.crc;
  Receiver rx;
  std::size_t from = 0;
  for (const std::size_t cut : cuts) {
    rx.feed(std::span(b).subspan(from, cut - from), 0ms, r);
    from = cut;
  }
  rx.feed(std::span(b).subspan(from), 0ms, r);
  return r;
}

void expect_result(const Case& c, const Recorder& r, const std::string& how) {
  EXPECT_EQ(r.frames, c.frames) << c.name << " " << how;
  EXPECT_EQ(r.drops, c.drops) << c.name << " " << how;
  EXPECT_EQ(r.garbage, c.garbage) << c.name << " " << how;
}

TEST(Receiver, CasesWholeSplitAndByteByByte) {
  for (const auto& c : cases()) {
    const std::size_t n = bytes(c.input).size();
    expect_result(c, run(c, {}), "whole");
    for (std::size_t cut = 0; cut <= n; ++cut) expect_result(c, run(c, {cut}), "cut at " + std::to_string(cut));
    std::vector<std::size_t> every;
    for (std::size_t i = 1; i < n; ++i) every.push_back(i);
    expect_result(c, run(c, every), "byte by byte");
  }
}

TEST(Receiver, InterByteTimeout) {
  const auto f = bytes(k_read);
  const auto first = std::span(f).first(4);
  const auto rest = std::span(f).subspan(4);
  {  // exactly 50 ms between two bytes: still one frame
    Recorder r;
    Receiver rx;
    rx.feed(first, 1000ms, r);
    rx.feed(rest, 1050ms, r);
    EXPECT_EQ(r.frames.size(), 1u);
    EXPECT_TRUE(r.drops.empty());
  }
  {  // 51 ms: the partial frame is dropped, its tail is garbage, the next frame is fine
    Recorder r;
    Receiver rx;
    rx.feed(first, 1000ms, r);
    rx.feed(rest, 1051ms, r);
    EXPECT_TRUE(r.frames.empty());
    EXPECT_EQ(r.drops, std::vector<std::string>{"timeout: 53 07 01 01"});
    EXPECT_EQ(r.garbage, rest.size());
    rx.feed(f, 1052ms, r);
    EXPECT_EQ(r.frames.size(), 1u);
  }
  {  // the gap counts between bytes, not from the frame's start
    Recorder r;
    Receiver rx;
    for (std::size_t i = 0; i < f.size(); ++i) rx.feed(std::span(f).subspan(i, 1), Millis(40 * i), r);
    EXPECT_EQ(r.frames.size(), 1u);
  }
  {  // a timeout right after SOF: the new byte starts afresh (here: a new frame)
    Recorder r;
    Receiver rx;
    rx.feed(std::span(f).first(1), 0ms, r);
    rx.feed(f, 60ms, r);
    EXPECT_EQ(r.drops, std::vector<std::string>{"timeout: 53"});
    EXPECT_EQ(r.frames.size(), 1u);
  }
  {  // bytes scanned again after a wrong E keep their arrival times
    Recorder r;
    Receiver rx;
    rx.feed(bytes("53 05"), 0ms, r);
    rx.feed(f, 30ms, r);  // "53 05 53 07 01 01 41": no E; the frame at the second S is complete
    EXPECT_EQ(r.frames.size(), 1u);
  }
}

TEST(Receiver, CrcSwitchActsOnTheNextFrameOfTheSameChunk) {
  // The first frame's handler turns the check off (0x2400.04 bit 23): the second frame, with a wrong
  // CRC, in the same chunk, is accepted.
  const auto b = bytes(k_read + "53 07 01 01 41 60 00 00 45");
  Recorder r;
  r.on = [&r](const FrameView&) { r.crc = false; };
  Receiver rx;
  rx.feed(b, 0ms, r);
  EXPECT_EQ(r.frames.size(), 2u);
}

TEST(Receiver, ResetDropsThePartialFrame) {
  const auto f = bytes(k_read);
  Recorder r;
  Receiver rx;
  rx.feed(std::span(f).first(5), 0ms, r);
  EXPECT_EQ(rx.partial(), 5u);
  rx.reset();
  EXPECT_EQ(rx.partial(), 0u);
  rx.feed(std::span(f).subspan(5), 0ms, r);
  rx.feed(f, 0ms, r);
  EXPECT_EQ(r.frames.size(), 1u);
}

TEST(Receiver, BoundedOnNoise) {
  // Pseudo-random bytes rich in S: the receiver never holds more than one frame.
  Recorder r;
  r.crc = false;
  Receiver rx;
  std::uint32_t x = 12345;
  std::vector<std::uint8_t> noise(200000);
  for (auto& b : noise) {
    x = x * 1103515245u + 12345u;
    const auto v = static_cast<std::uint8_t>(x >> 16);
    b = (v % 5 == 0) ? k_sof : (v % 7 == 0 ? k_eof : v);
  }
  for (std::size_t i = 0; i < noise.size(); i += 1000) {
    rx.feed(std::span(noise).subspan(i, 1000), Millis(i / 1000), r);
    ASSERT_LE(rx.partial(), k_max_frame - 1);
  }
  // a good frame still gets through after the noise (after a pause that ends any partial frame)
  r.frames.clear();
  rx.feed(bytes(k_read), 10000ms, r);
  EXPECT_EQ(r.frames, std::vector<std::string>{"53 07 01 01 41 60 00 73 45"});
}

TEST(Receiver, DropReasonNames) {
  EXPECT_EQ(to_string(DropReason::garbage), "garbage before SOF");
  EXPECT_EQ(to_string(DropReason::bad_length), "L < 4");
  EXPECT_EQ(to_string(DropReason::bad_eof), "no E");
  EXPECT_EQ(to_string(DropReason::bad_crc), "bad CRC");
  EXPECT_EQ(to_string(DropReason::timeout), "timeout");
}

}  // namespace
}  // namespace mcemu::faulhaber
