// scripting.md §12: for each public example script, a script of our own that uses the same calls in
// the same way, and that row's observable effect, with the real python3 in lock-step drive time.
// (Fullmo's files are not copied; the HTTP/UDP-level versions follow with the web wiring.)
#include <gtest/gtest.h>

#include <algorithm>

#include "protocols/refgo/session.hpp"
#include "tests/scripting/engine_fixture.hpp"

namespace mcemu::scripting::test {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The parameter-list helper of several examples: Kickdrive object lists parsed with split/rstrip/int.
const std::string k_list_writer =
    "def WriteObjectsFromKickdriveList(text):\n"
    "    params = [line.split(',') for line in text.split('\\n') if line.strip()]\n"
    "    for param in params:\n"
    "        if len(param) < 2:\n"
    "            continue\n"
    "        id = param[0].split('.')\n"
    "        index = int(id[1].rstrip('h'), 16)\n"
    "        subindex = int(id[2].rstrip('h'), 16)\n"
    "        value = int(param[2].split('#')[0])\n"
    "        mc.WriteObject(index, subindex, value)\n"
    "        print (\"Writing object \" + hex(index) + \",\" + hex(subindex) + \" = \" + str(value))\n";

TEST(Examples, ModuleOverviewRunsToTheEndInSod) {  // mcdriveModuleOverview.py
  EngineRig r;
  const std::string src =
      "# overview of our own\n#id overview test\nimport mcdrive as mc\nimport sys\n"
      "mc.WriteObject(0x6092, 0x01, 360)\n"
      "print ('mc.ChkError() = %d' % mc.ChkError())\n"
      "for x in range(0, 15):\n    print ('mc.ChkMfrStatus(%d) = %d' % (x, mc.ChkMfrStatus(x)))\n"
      "for x in range(1, 8):\n    print ('mc.ChkIn(%d) = %d' % (x, mc.ChkIn(x)))\n"
      "mc.WriteObject(0x6060, 0x0, 0)\nprint('mc.ReadObject(0x6041, 0x0) = %d' % mc.ReadObject(0x6041, 0x0))\n"
      "mc.WriteControl(0x80)\nmc.EnableDrive()\nmc.SetTargetPos(100)\nmc.SetPosVel(200)\nmc.SetOpMode(1)\n"
      "mc.WriteControl(0x1f)\nwhile (mc.ChkReady() == 0):\n    sys.wait(1)\n"
      "mc.GoPosAbs(1000)\nwhile (mc.ChkReady() == 0):\n    sys.wait(1)\n"
      "mc.GoPosAbs(-1000)\nwhile (mc.ChkReady() == 0):\n    sys.wait(1)\n"
      "mc.GoPosRel(2000)\nwhile (mc.ChkReady() == 0):\n    sys.wait(1)\n"
      "mc.GoPosRel(0)\nwhile (mc.ChkReady() == 0):\n    sys.wait(1)\n"
      "mc.GoVel(1440)\nsys.wait(3000)\nmc.GoVel(-1440)\nsys.wait(3000)\n"
      "print ('mc.GetActualPos() = %d' % mc.GetActualPos())\nmc.GoVel(0)\nsys.wait(1000)\n"
      "print ('mc.GetOpMode() = %d' % mc.GetOpMode())\nmc.SetOpMode(1)\nprint ('mc.GetOpMode() = %d' % "
      "mc.GetOpMode())\n"
      "mc.SetOut(1)\nmc.SetOut(4)\nprint ('mc.ReadObject(0x60fe, 0x1) = %d' % mc.ReadObject(0x60fe, 0x1))\n"
      "mc.ClearOut(1)\nmc.ClearOut(4)\nmc.PowerQuit()\n#private\nprint ('Finished')\n";
  ASSERT_TRUE(r.run(src, 60000)) << r.text();
  const std::string t = r.text();
  EXPECT_EQ(count(t, "mc.ChkError() = 0\r\n"), 1U) << t;
  EXPECT_EQ(count(t, "mc.ChkMfrStatus("), 15U);
  EXPECT_EQ(count(t, "mc.ChkIn("), 7U);
  EXPECT_NE(t.find("mc.GetOpMode() = 3\r\nmc.GetOpMode() = 1\r\n"), std::string::npos);
  EXPECT_NE(t.find("mc.ReadObject(0x60fe, 0x1) = 589824\r\n"), std::string::npos);
  EXPECT_TRUE(t.ends_with("Finished\r\n")) << t;
  EXPECT_EQ(r.get(0x6041) & 0x4F, 0x40);  // switch on disabled
  EXPECT_EQ(r.engine->source_visible().find("Finished"), std::string::npos);
}

TEST(Examples, SimplePosTestCyclesWithOut1DuringTheMoveToZero) {  // driveSimplePosTest.py (+ `import drive`)
  for (const std::string module : {"mcdrive as mc", "drive as mc"}) {
    EngineRig r;
    r.start("#id simple pos\nimport sys\nimport " + module +
            "\ndef WaitTargetReached():\n\twhile (mc.ChkReady() == 0):\n\t\tsys.wait(1)\n"
            "\twhile (mc.ChkError() != 0):\n\t\tsys.wait(1)\n\tif mc.ChkIn(2) == 0:\n\t\tsys.wait(1000)\n"
            "sys.wait(2000)\nmc.WriteObject(0x6092, 0x01, 360)\nmc.EnableDrive()\nmc.SetAcc(500)\nmc.SetDec(500)\n"
            "mc.SetPosVel(360)\nwhile(1):\n\tmc.SetOut(1)\n\tmc.GoPosAbs(0)\n\tWaitTargetReached()\n\tmc.ClearOut(1)\n"
            "\tmc.GoPosAbs(1000)\n\tWaitTargetReached()\n\tmc.GoPosAbs(180)\n\tWaitTargetReached()\n");
    std::vector<std::int64_t> targets;
    bool out1_wrong = false;
    ASSERT_TRUE(r.advance_until(
        [&] {
          const std::int64_t t = r.get(0x607A);
          if (r.engine->state() == RunState::run && (targets.empty() || targets.back() != t)) targets.push_back(t);
          const bool out1 = (r.get(0x60FE, 1) >> 16) & 1;
          if (!targets.empty() && ((targets.back() == 0) != out1) && r.get(0x6041) & 0x0100) out1_wrong = true;
          return targets.size() >= 5;
        },
        60000));
    EXPECT_EQ(std::vector<std::int64_t>(targets.begin(), targets.begin() + 5),
              (std::vector<std::int64_t>{0, 1000, 180, 0, 1000}));
    EXPECT_FALSE(out1_wrong);
    r.engine->stop();
  }
}

TEST(Examples, SoftlimitBackForthAbortsThenOscillates) {  // driveSoftlimitBackForth.py (MCFLAT)
  const std::string src =
      "import sys\nimport mcdrive as mc\ndef WaitTargetReached():\n\twhile (mc.ChkReady() == 0):\n\t\tsys.wait(1)\n"
      "\twhile (mc.ChkError() != 0):\n\t\tsys.wait(1)\nsoftLimitMin = mc.ReadObject(0x607d, 1)\n"
      "softLimitMax = mc.ReadObject(0x607d, 2)\n"
      "if ((softLimitMin == 0 and softLimitMax == 0) or softLimitMax <= (softLimitMin + 1000)):\n"
      "\tprint(\"demo abort. Check softlimit objects 607Dh.1h and 607Dh.2h!\")\nelse:\n    sys.wait(5000)\n"
      "    mc.EnableDrive()\n    mc.SetPosVel(50000)\n    while (1):\n        mc.GoPosAbs(softLimitMin)\n"
      "        WaitTargetReached()\n        mc.GoPosAbs(softLimitMax)\n        WaitTargetReached()\n";
  EngineRig r("MCFLAT");
  ASSERT_TRUE(r.run(src));
  EXPECT_NE(r.text().find("demo abort."), std::string::npos);
  ASSERT_EQ(r.write(0x607D, 1, 10000), od::AbortCode::none);
  ASSERT_EQ(r.write(0x607D, 2, 60000), od::AbortCode::none);
  r.start(src);
  int arrivals = 0;
  std::int64_t last = -1;
  ASSERT_TRUE(r.advance_until(
      [&] {
        const std::int64_t p = r.get(0x6064);
        for (const std::int64_t lim : {10000, 60000}) {
          if (std::abs(p - lim) < 50 && last != lim) {
            last = lim;
            ++arrivals;
          }
        }
        return arrivals >= 4;
      },
      60000));
  r.engine->stop();
}

TEST(Examples, RefgoCommandsFromAPoweredOffDrive) {  // UsingRefGoCommandsFromPythonScript.py
  EngineRig r;
  r.start(
      "import sys\nimport refgo\nsys.wait(5000)\nrefgo.cmd(\"G10000\")\nwhile (refgo.cmd(\"TS\") != 1):\n\tpass\n"
      "while(1):\n    refgo.cmd(\"GW1000\")\n    while (refgo.cmd(\"TS\") != 1):\n        pass\n    sys.wait(1000)\n");
  ASSERT_TRUE(r.advance_until([&] { return r.get(0x607A) == 1000 && r.get(0x6064) > 10500; }, 60000)) << r.get(0x6064);
  EXPECT_TRUE(r.advance_until([&] { return r.get(0x6064) >= 12000 - 2; }, 60000)) << r.get(0x6064);
  r.engine->stop();
}

TEST(Examples, JogWithLifetimeUsesTheBuiltInTimedJog) {  // refGoExtensionExampleJogWithLifetime.py
  EngineRig r;
  refgo::Session client(r.in);
  r.start(
      "import sys\nimport refgo\nrefgo.open(\"refgo\", 0)\nwhile (1):\n\tcmd = refgo.read(0, 0)\n"
      "\tif cmd is not None:\n\t\tif (cmd.upper().startswith(\"JP\")):\n\t\t\tprint('script saw it')\n\tsys.wait(5)\n");
  r.advance(200);
  client.receive("JP500\r");
  EXPECT_EQ(client.take_output(), "JP500\r\n>");  // known: the built-in interpreter answers (mode 2)
  const std::uint64_t t0 = r.core.time_ms();
  EXPECT_NE(r.get(0x60FF), 0);
  ASSERT_TRUE(r.advance_until([&] { return r.get(0x60FF) == 0; }, 2000));
  EXPECT_EQ(r.core.time_ms() - t0, 500U);
  EXPECT_EQ(r.text().find("script saw it"), std::string::npos);  // not forwarded
  r.engine->stop();
}

TEST(Examples, MaxTrackN23DemoCyclesAndFastMode) {  // maxTRACK_N23_Messedemo.py (MCN23, `import drive`)
  EngineRig r("MCN23");
  r.start(
      "#id maxTRACK N23 demo rev8\nimport drive\nimport sys\ndef moveAndWait(newPos):\n"
      "    if drive.ChkIn(1) > 0:\n        sys.wait(1000)\n        drive.SetAcc(1500)\n        drive.SetDec(1500)\n"
      "        drive.SetPosVel(750)\n    else:\n        sys.wait(3000)\n        drive.SetAcc(500)\n"
      "        drive.SetDec(500)\n        drive.SetPosVel(300)\n    drive.GoPosAbs(newPos)\n"
      "    drive.WriteControl(0x3F)\n    timeout = sys.time() + 10000\n"
      "    while (drive.ChkReady() == 0 and sys.time() < timeout):\n        sys.wait(1)\n"
      "    if (drive.ChkError() == 1):\n        drive.PowerQuit()\n        sys.wait(10000)\n        "
      "drive.EnableDrive()\n"
      "sys.wait(5000)\nwhile (1):\n    drive.EnableDrive()\n    sys.wait(2000)\n    moveAndWait(20)\n"
      "    moveAndWait(50)\n    moveAndWait(300)\n    moveAndWait(650)\n    moveAndWait(10)\n    sys.wait(1000)\n"
      "    drive.PowerQuit()\n    sys.wait(2000)\n");
  ASSERT_EQ(r.in.execute("OW 3510H,1H,65536"), "OW 3510H,1H,65536\r\nOW 3510H,1H,65536,OK\r\n>");  // fast mode
  std::vector<std::int64_t> targets;
  ASSERT_TRUE(r.advance_until(
      [&] {
        const std::int64_t t = r.get(0x607A);
        if (r.get(0x6041) & 0x0100 && (targets.empty() || targets.back() != t)) targets.push_back(t);
        return targets.size() >= 5;
      },
      120000));
  EXPECT_EQ(targets, (std::vector<std::int64_t>{20, 50, 300, 650, 10}));
  EXPECT_EQ(r.get(0x6081), 750);  // IN1 high: the fast parameters
  r.engine->stop();
}

TEST(Examples, FlatTrackDemoWritesJerkAndMovesBetweenLimitTargets) {  // flatTRACK_demo.py (MCFLAT)
  EngineRig r("MCFLAT");
  ASSERT_EQ(r.write(0x607D, 1, 0), od::AbortCode::none);
  ASSERT_EQ(r.write(0x607D, 2, 100000), od::AbortCode::none);
  r.start(
      "import sys\nimport mcdrive as mc\ndef WaitTargetReached():\n\twhile (mc.ChkReady() == 0):\n\t\tsys.wait(1)\n"
      "\twhile (mc.ChkError() != 0):\n\t\tsys.wait(1)\nsoftLimitMin = mc.ReadObject(0x607d, 1)\n"
      "softLimitMax = mc.ReadObject(0x607d, 2)\nif ((softLimitMax - softLimitMin < 50000) or softLimitMax > 999999):\n"
      "\tprint(\"abort\")\nelse:\n\tsys.wait(5000)\n\tmc.EnableDrive()\n\twhile(1):\n\t\tmc.SetAcc(50)\n"
      "\t\tmc.WriteObject(0x60A4, 0, 1000)\n\t\tmc.SetPosVel(50000)\n\t\tmc.GoPosAbs(softLimitMin + 5000)\n"
      "\t\tWaitTargetReached()\n\t\tsys.wait(2000)\n\t\tmc.SetAcc(10000)\n\t\tmc.WriteObject(0x60A4, 0, 500000)\n"
      "\t\tmc.SetPosVel(200000)\n\t\tmc.GoPosAbs(softLimitMax - 5000)\n\t\tWaitTargetReached()\n\t\tsys.wait(2000)\n");
  bool low = false;
  ASSERT_TRUE(r.advance_until(
      [&] {
        const std::int64_t p = r.get(0x6064);
        if (std::abs(p - 5000) < 100) low = true;
        return low && std::abs(p - 95000) < 100 && r.get(0x60A4) == 500000;
      },
      120000))
      << r.get(0x6064);
  r.engine->stop();
}

TEST(Examples, ShortTrackSmoothBackAndForth) {  // shorttrack_smooth_back_and_forth.py (MCSHORT)
  EngineRig r("MCSHORT");
  ASSERT_EQ(r.write(0x607D, 1, 2000), od::AbortCode::none);
  ASSERT_EQ(r.write(0x607D, 2, 20000), od::AbortCode::none);
  r.start(
      "import sys\nimport mcdrive as mc\nPARAMS = \"\"\"\n050.6067h.00h,unsigned32,50 # Position window\n"
      "050.6081h.00h,unsigned32,17000 # Profile_velocity\n\"\"\"\n" +
      k_list_writer +
      "def main():\n    WriteObjectsFromKickdriveList(PARAMS)\n    softLimitMin = mc.ReadObject(0x607d, 1)\n"
      "    softLimitMax = mc.ReadObject(0x607d, 2)\n    if softLimitMax <= softLimitMin + 1000:\n        return\n"
      "    sys.wait(5000)\n    mc.EnableDrive()\n    while(1):\n        mc.GoPosAbs(softLimitMin)\n"
      "        ChkReady()\n        mc.GoPosAbs(softLimitMax)\n        ChkReady()\n"
      "def ChkReady():\n    sys.wait(100)\n    while (mc.ChkReady() == 0):\n        sys.wait(1)\nmain()\n");
  int ends = 0;
  std::int64_t last = -1;
  ASSERT_TRUE(r.advance_until(
      [&] {
        const std::int64_t p = r.get(0x6064);
        for (const std::int64_t lim : {2000, 20000}) {
          if (std::abs(p - lim) < 60 && last != lim) {
            last = lim;
            ++ends;
          }
        }
        return ends >= 3;
      },
      60000));
  EXPECT_NE(r.text().find("Writing object 0x6067,0x0 = 50\r\nWriting object 0x6081,0x0 = 17000\r\n"),
            std::string::npos);
  r.engine->stop();
}

TEST(Examples, RampTestingWritesItsStatusObject) {  // standard_ramp_testing.py (MCFLAT)
  EngineRig r("MCFLAT");
  ASSERT_EQ(r.write(0x607D, 2, 200000), od::AbortCode::none);
  r.start(
      "import sys\nimport mcdrive as mc\ndef WaitTargetReached():\n\twhile (mc.ChkReady() == 0):\n\t\tsys.wait(1)\n"
      "def doRamp(runNo, target, speed, acc, jrk):\n\tmc.SetAcc(acc)\n\tmc.SetDec(acc)\n"
      "\tmc.WriteObject(0x60A4, 0, jrk)\n\tmc.SetPosVel(speed)\n\tmc.WriteObject(0x340c, 0x01, runNo)\n"
      "\tmc.GoPosAbs(target)\n\tWaitTargetReached()\n\tmc.WriteObject(0x340c, 0x01, 0)\n\tsys.wait(200)\n"
      "\tmc.WriteObject(0x340c, 0x01, -runNo)\n\tmc.GoPosAbs(0)\n\tWaitTargetReached()\n"
      "\tmc.WriteObject(0x340c, 0x01, 0)\nmc.WriteObject(0x340c, 0x01, 0)\nmc.EnableDrive()\n"
      "doRamp(1, 200000 // 10, 5000, 500, 5000)\nprint('ramps done')\n");
  std::vector<std::int64_t> states;
  ASSERT_TRUE(r.advance_until(
      [&] {
        const std::int64_t s = r.get(0x340C, 1);
        if (states.empty() || states.back() != s) states.push_back(s);
        return r.engine->state() == RunState::off;
      },
      120000));
  EXPECT_EQ(states, (std::vector<std::int64_t>{0, 1, 0, -1, 0}));
  EXPECT_NE(r.text().find("ramps done"), std::string::npos) << r.text();
}

TEST(Examples, IoExamplesWriteTheirListsAndEnd) {  // the two "IO Example CODE" scripts of group 2
  for (const std::string model : {"MC349", "MCFLAT"}) {
    EngineRig r(model);
    const std::string src =
        "import sys\nimport mcdrive as mc\nSETUP = \"\"\"\n"
        "050.6073h.00h,unsigned16,1000 # Max. Current/Torque [0.1%]\n"
        "050.607dh.02h,integer32,360 # Softlimit - Max Pos [user units]\n\"\"\"\n"
        "APP = \"\"\"\n050.3511h.01h,unsigned16,1536 # IN1 function\n"
        "050.3611h.01h,unsigned16,6 # OUT1 function\n\"\"\"\n" +
        k_list_writer + "WriteObjectsFromKickdriveList(SETUP)\nWriteObjectsFromKickdriveList(APP)\n";
    ASSERT_TRUE(r.run(src)) << model;
    EXPECT_EQ(count(r.text(), "Writing object "), 4U) << r.text();
    EXPECT_EQ(r.get(0x3511, 1), 1536);
    EXPECT_EQ(r.get(0x3611, 1), 6);
    EXPECT_EQ(r.get(0x607D, 2), 360);
  }
}

TEST(Examples, ThreeAxisBaseIgnoresTheOldRabbitObjects) {  // 3axis_flattrack_axix1_x_base.py (MCFLAT)
  EngineRig r("MCFLAT");
  ASSERT_TRUE(
      r.run("import sys\nimport mcdrive as mc\nL = \"\"\"\n050.3304h.01h,unsigned32,5000 # filter\n"
            "050.3305h.03h,unsigned32,200 # milliQ\n\"\"\"\n" +
            k_list_writer +
            "WriteObjectsFromKickdriveList(L)\nprint(mc.WriteObject(0x3304, 1, 5000))\n"
            "softLimitMin = mc.ReadObject(0x607d, 1)\nsoftLimitMax = mc.ReadObject(0x607d, 2)\n"
            "if ((softLimitMin == 0 and softLimitMax == 0) or softLimitMax <= (softLimitMin + 1000)):\n"
            "    print(\"abort\")\n    sys.exit()\nprint('never')\n"));
  EXPECT_NE(r.text().find("100794368\r\nabort\r\n"), std::string::npos) << r.text();
  EXPECT_EQ(r.text().find("never"), std::string::npos);
}

}  // namespace
}  // namespace mcemu::scripting::test
