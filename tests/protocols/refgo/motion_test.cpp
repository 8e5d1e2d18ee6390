// Motion and power commands against the real drive core (refgo.md §7, acceptance test 7 of §15,
// transcripts §14.1 and §14.2).
#include <gtest/gtest.h>

#include "protocols/refgo/session.hpp"
#include "tests/protocols/refgo/refgo_fixture.hpp"

namespace mcemu::refgo {
namespace {

using test::Drive;
using test::matches_vector;

TEST(Motion, GFromSwitchOnDisabledEnablesAndMoves) {
  Drive d;
  EXPECT_EQ(d.ts(), "0");
  EXPECT_EQ(d.tpsr(), "00000002");
  Session s(d.in);
  s.receive("G1000\rTS\r");  // one segment, from SOD (§14.5)
  EXPECT_EQ(s.take_output(), "G1000\r\n>TS\r\n2\r\n>");
  EXPECT_EQ(d.get(0x6061), 1);
  EXPECT_EQ(d.get(0x607A), 1000);
  EXPECT_EQ(d.sw() & 0x6F, 0x27);
  EXPECT_LE(d.step_until([&] { return d.reached(); }, 10000), 10000U);
  EXPECT_EQ(d.tp(), 1000);
  EXPECT_EQ(d.tpsr(), "0000010a");
  EXPECT_EQ(d.ts(), "1");
}

TEST(Motion, GWithoutArgumentUsesPoAndGwIsRelative) {
  Drive d;
  EXPECT_EQ(d.run("PO500"), "PO500\r\n>");
  EXPECT_EQ(d.ts(), "0");  // PO does not move or enable
  EXPECT_EQ(d.run("G"), "G\r\n>");
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.tp(), 500);
  EXPECT_EQ(d.run("WA-200"), "WA-200\r\n>");
  EXPECT_EQ(d.run("GW"), "GW\r\n>");
  d.step(1);
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.tp(), 300);
  EXPECT_EQ(d.run("GW100"), "GW100\r\n>");
  d.step(1);
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.tp(), 400);
}

TEST(Motion, GInFaultDoesNotMoveButKeepsTheTarget) {
  Drive d;
  d.core.inject(core::FaultCause::under_voltage);
  d.step(50);
  ASSERT_EQ(d.ts(), "9");
  EXPECT_EQ(d.run("G1000"), "G1000\r\n>");
  d.step(100);
  EXPECT_EQ(d.ts(), "9");
  EXPECT_EQ(d.tp(), 0);
  EXPECT_EQ(d.get(0x607A), 1000);  // kept for a later G (§7.2)
  // PWC from F with the cause gone reaches OE (fault reset included).
  d.core.clear(core::FaultCause::under_voltage);
  d.step(50);
  EXPECT_EQ(d.run("PWC"), "PWC\r\n>");
  EXPECT_EQ(d.sw() & 0x6F, 0x27);
  EXPECT_EQ(d.ts(), "1");
  EXPECT_EQ(d.get(0x6060), 1);
  EXPECT_EQ(d.run("G"), "G\r\n>");
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.tp(), 1000);
}

TEST(Motion, PqEndsInSwitchOnDisabledWithModeZero) {
  Drive d;
  EXPECT_EQ(d.run("PWC"), "PWC\r\n>");
  EXPECT_EQ(d.tpsr(), "00000102");  // powered, target not yet reached
  d.step_until([&] { return d.reached(); }, 1000);
  EXPECT_EQ(d.tpsr(), "0000010a");
  EXPECT_EQ(d.run("PQ"), "PQ\r\n>");
  EXPECT_EQ(d.get(0x6060), 0);
  EXPECT_EQ(d.sw() & 0x4F, 0x40);
  EXPECT_EQ(d.ts(), "0");
  EXPECT_EQ(d.run("PQ1"), "PQ1\r\nPQ1,ERROR,08000000h\r\n>");
}

TEST(Motion, SmQuickStopsAndCmResumesToTheOldTarget) {
  Drive d;
  d.run("SP720");
  d.run("G720000");  // about 11 turns at 720 rpm
  d.step(200);
  ASSERT_EQ(d.ts(), "2");
  EXPECT_EQ(d.run("SM"), "SM\r\n>");
  EXPECT_EQ(d.get(0x605A), 6);
  EXPECT_EQ(d.sw() & 0x6F, 0x07);  // QSA
  d.step_until([&] { return d.ts() == "1"; }, 5000);
  const auto stopped_at = d.tp();
  EXPECT_LT(stopped_at, 720000);
  d.step(50);
  EXPECT_EQ(d.sw() & 0x6F, 0x07);  // stays in QSA
  EXPECT_EQ(d.run("CM"), "CM\r\n>");
  EXPECT_EQ(d.sw() & 0x6F, 0x27);
  d.step(1);
  d.step_until([&] { return d.reached(); }, 20000);
  EXPECT_EQ(d.tp(), 720000);
  EXPECT_EQ(d.run("CM"), "CM\r\n>");  // outside QSA: no effect
  EXPECT_EQ(d.tp(), 720000);
}

TEST(Motion, JogWithTimeStopsAfterTheTime) {
  Drive d;
  d.run("SP720");
  EXPECT_EQ(d.run("JP500"), "JP500\r\n>");
  EXPECT_EQ(d.get(0x6061), 3);
  EXPECT_EQ(d.get(0x60FF), 720);
  ASSERT_TRUE(d.in.programs().jog_stop_due_ms());
  const auto t0 = d.core.time_ms();
  const auto steps = d.step_until([&] { return d.get(0x60FF) == 0; }, 1000);
  EXPECT_GE(steps, 499U);
  EXPECT_LE(steps, 501U);
  EXPECT_EQ(d.core.time_ms() - t0, steps);
  d.step_until([&] { return d.ts() == "1"; }, 5000);
  EXPECT_EQ(d.sw() & 0x6F, 0x27);  // stays OE in mode 3
  EXPECT_EQ(d.get(0x6061), 3);
}

TEST(Motion, JogSpeedFollowsSpAndAnotherCommandDisarmsTheTimer) {
  Drive d;
  d.run("SP1000");
  EXPECT_EQ(d.run("JN2000"), "JN2000\r\n>");
  EXPECT_EQ(d.get(0x60FF), -1000);
  d.step(100);
  EXPECT_EQ(d.run("SP500"), "SP500\r\n>");
  EXPECT_EQ(d.get(0x60FF), -500);
  EXPECT_TRUE(d.in.programs().jog_stop_due_ms());  // SP keeps the timer
  EXPECT_EQ(d.run("JP"), "JP\r\n>");               // no time: jog until another command
  EXPECT_FALSE(d.in.programs().jog_stop_due_ms());
  EXPECT_EQ(d.get(0x60FF), 500);
  d.step(2500);
  EXPECT_EQ(d.get(0x60FF), 500);
  EXPECT_EQ(d.run("JP100"), "JP100\r\n>");
  EXPECT_EQ(d.run("SM"), "SM\r\n>");
  EXPECT_FALSE(d.in.programs().jog_stop_due_ms());
}

TEST(Motion, JogOnRabbitIsAnError) {
  Drive d("MCFLAT");
  EXPECT_EQ(d.run("JP"), "JP\r\nJP,ERROR,06090030h\r\n>");
  EXPECT_EQ(d.run("JN 10"), "JN 10\r\nJN 10,ERROR,06090030h\r\n>");
  EXPECT_EQ(d.run("ACV100"), "ACV100\r\n>");
  EXPECT_EQ(d.get(0x60A4), 100);
}

TEST(Motion, BackAndForthOscillatesWithDwellUntilSm) {
  Drive d;
  d.run("SP3600");
  d.run("AC100000");
  d.run("DE100000");
  d.run("G1000");
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.run("RW100"), "RW100\r\n>");
  EXPECT_EQ(d.run("WT200"), "WT200\r\n>");
  EXPECT_EQ(d.run("RR"), "RR\r\n>");
  ASSERT_TRUE(d.in.programs().back_and_forth_active());
  EXPECT_EQ(d.get(0x607A), 1100);
  for (int cycle = 0; cycle < 2; ++cycle) {
    for (std::int64_t target : {1100, 1000}) {
      // moving (TS 2) until the target is reached, then a 200 ms dwell (TS 1)
      EXPECT_EQ(d.ts(), "2");
      EXPECT_LE(d.step_until([&] { return d.reached(); }, 5000), 5000U);
      EXPECT_EQ(d.tp(), target);
      const auto dwell = d.step_until([&] { return d.ts() == "2"; }, 1000);
      EXPECT_GE(dwell, 199U);
      EXPECT_LE(dwell, 202U);
    }
  }
  EXPECT_EQ(d.run("SM"), "SM\r\n>");
  EXPECT_FALSE(d.in.programs().back_and_forth_active());
  d.step(2000);
  EXPECT_EQ(d.ts(), "1");
}

// §7.7 step 1: the base is the target of the last accepted set-point "even if that move was
// interrupted", not where the drive stopped.
TEST(Motion, BackAndForthAfterAnInterruptedMoveStartsFromTheLastAcceptedTarget) {
  Drive d;
  d.run("SP720");
  d.run("G720000");
  d.step(200);
  ASSERT_EQ(d.ts(), "2");
  EXPECT_EQ(d.run("SM"), "SM\r\n>");
  d.step_until([&] { return d.ts() == "1"; }, 5000);
  const auto stopped_at = d.tp();
  ASSERT_LT(stopped_at, 700000);
  EXPECT_EQ(d.run("PWC"), "PWC\r\n>");
  ASSERT_EQ(d.sw() & 0x6F, 0x27);
  EXPECT_EQ(d.run("RW100"), "RW100\r\n>");
  EXPECT_EQ(d.run("RR"), "RR\r\n>");
  ASSERT_TRUE(d.in.programs().back_and_forth_active());
  EXPECT_EQ(d.get(0x607A), 720100);  // base + RWAY, base = 720000
  d.step(1);
  EXPECT_LE(d.step_until([&] { return d.reached(); }, 20000), 20000U);
  EXPECT_EQ(d.tp(), 720100);
  EXPECT_LE(d.step_until([&] { return d.get(0x607A) == 720000; }, 1000), 1000U);  // and back to the base
  d.step(1);
  EXPECT_LE(d.step_until([&] { return d.reached(); }, 5000), 5000U);
  EXPECT_EQ(d.tp(), 720000);
}

TEST(Motion, BackAndForthStopsOnAnyMotionCommandOrWrite) {
  Drive d;
  d.run("G0");
  d.step_until([&] { return d.reached(); }, 10000);
  EXPECT_EQ(d.run("RR-500"), "RR-500\r\n>");
  EXPECT_EQ(d.in.variables().repeat_way, -500);
  EXPECT_TRUE(d.in.programs().back_and_forth_active());
  d.step(10);
  // a controlword write from another source (here: the SDO origin)
  d.od.write(0x6040, 0, od::Value{std::int64_t{0x000F}}, od::Origin::sdo);
  EXPECT_FALSE(d.in.programs().back_and_forth_active());
  // RR with way 0 does nothing
  d.run("RW0");
  EXPECT_EQ(d.run("RR"), "RR\r\n>");
  EXPECT_FALSE(d.in.programs().back_and_forth_active());
  // a mode change stops it too
  d.run("RR300");
  EXPECT_TRUE(d.in.programs().back_and_forth_active());
  d.run("OW6060,0,3");
  EXPECT_FALSE(d.in.programs().back_and_forth_active());
}

TEST(Motion, RefHomesAndRef35SetsHomeWhenNotEnabled) {
  Drive d;
  d.run("G0");  // enable, then power off again
  d.run("PQ");
  d.set(0x607C, 0, 0);
  EXPECT_EQ(d.run("REF"), "REF\r\n>");  // REF alone: no effect
  EXPECT_EQ(d.run("REF35"), "REF35\r\n>");
  EXPECT_EQ(d.get(0x6098), 35);
  EXPECT_EQ(d.get(0x6060), 6);
  EXPECT_EQ(d.ts(), "0");  // power state unchanged
  EXPECT_EQ(d.tp(), 0);
  d.set(0x607C, 0, 123);
  d.run("REF37");
  EXPECT_EQ(d.tp(), 123);
  EXPECT_EQ(d.run("REF200"), "REF200\r\nREF200,ERROR,06090031h\r\n>");
  EXPECT_EQ(d.run("REF-200"), "REF-200\r\nREF-200,ERROR,06090032h\r\n>");
  EXPECT_EQ(d.get(0x6098), 37);
}

// §14.2: the 2021 session from a powered-off drive, with the current firmware's TPSR.
TEST(Transcripts, Session2021) {
  Drive d;
  Session s(d.in);
  const auto send = [&](const std::string& line) {
    s.receive(line + "\r");
    return s.take_output();
  };
  EXPECT_EQ(send("REF35"), "REF35\r\n>");
  EXPECT_EQ(send("SP720"), "SP720\r\n>");
  EXPECT_EQ(send("AC5000"), "AC5000\r\n>");
  EXPECT_EQ(send("DE1000"), "DE1000\r\n>");
  EXPECT_EQ(send("G360"), "G360\r\n>");
  d.step(100);
  EXPECT_EQ(send("G-7200"), "G-7200\r\n>");
  d.step(50);
  EXPECT_EQ(send("TPSR"), "TPSR\r\n00000106\r\n>");
  EXPECT_TRUE(matches_vector(send("TP"), "TP\r\n{TP}\r\n>"));
  ASSERT_LE(d.step_until([&] { return d.tpsr() == "0000010a"; }, 60000), 60000U);
  EXPECT_EQ(send("TPSR"), "TPSR\r\n0000010a\r\n>");
  EXPECT_EQ(send("TP"), "TP\r\n-7200\r\n>");
  EXPECT_EQ(send("PQ"), "PQ\r\n>");
  d.set(0x3511, 8, 110);
  EXPECT_EQ(send("OR3511,8"), "OR3511,8\r\nOR3511,8,110\r\n>");
  EXPECT_EQ(send("OW3511,8,120"), "OW3511,8,120\r\nOW3511,8,120,OK\r\n>");
  EXPECT_EQ(send("OR3511,8"), "OR3511,8\r\nOR3511,8,120\r\n>");
}

// §14.1: block homing in the negative direction against a mechanical stop, then a move to 0.
TEST(Transcripts, Session2022BlockHoming) {
  core::PlantConfig plant;
  plant.plant.set(&model::Plant::stops_inc,
                  core::StopRange{-30000, 1000000});  // raw increments; 360 user units per turn
  Drive d("MC349", plant);
  Session s(d.in);
  const auto send = [&](const std::string& line) {
    s.receive(line + "\r");
    return s.take_output();
  };
  EXPECT_EQ(send(""), ">");
  EXPECT_EQ(send("PWC"), "PWC\r\n>");
  for (const char* ow : {"OW6091,1,1", "OW6091,2,1", "OW6092,1,360", "OW6092,2,1", "OW6099,1,200", "OW609A,0,400",
                         "OW6073,0,200", "OW607C,0,-10"}) {
    EXPECT_EQ(send(ow), std::string(ow) + "\r\n" + ow + ",OK\r\n>");
  }
  EXPECT_EQ(send("REF-19"), "REF-19\r\n>");
  bool searching = false;
  bool at_block = false;
  for (int i = 0; i < 60000 && !at_block; ++i) {
    d.step();
    if (i % 10 != 0) continue;
    EXPECT_TRUE(matches_vector(send("TP"), "TP\r\n{TP}\r\n>"));
    const auto t = send("TPSR");
    if (t == "TPSR\r\n00000106\r\n>") searching = true;
    if (t == "TPSR\r\n0000010a\r\n>") at_block = true;
  }
  EXPECT_TRUE(searching);
  ASSERT_TRUE(at_block);
  EXPECT_TRUE(matches_vector(send("TP"), "TP\r\n{TP}\r\n>"));
  EXPECT_EQ(send("OW6073,0,1000"), "OW6073,0,1000\r\nOW6073,0,1000,OK\r\n>");
  EXPECT_EQ(send("G0"), "G0\r\n>");
  EXPECT_EQ(send("TPSR"), "TPSR\r\n00000106\r\n>");
  ASSERT_LE(d.step_until([&] { return d.tpsr() == "0000010a"; }, 60000), 60000U);
  EXPECT_EQ(send("TP"), "TP\r\n0\r\n>");
}

}  // namespace
}  // namespace mcemu::refgo
