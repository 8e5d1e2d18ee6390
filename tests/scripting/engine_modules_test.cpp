// The script's modules through the real engine (scripting.md §5–§9): mcdrive effects and errors,
// refgo.cmd and the attachment with real RefGo sessions, sys and time, strict mode.
#include <gtest/gtest.h>

#include "protocols/refgo/session.hpp"
#include "tests/scripting/engine_fixture.hpp"

namespace mcemu::scripting::test {
namespace {

// Runs `body` to its end and returns the printed lines (after the three code: lines).
std::vector<std::string> lines_of(EngineRig& r, const std::string& body, std::uint64_t max_ms = 20000) {
  EXPECT_TRUE(r.run(body, max_ms)) << r.text();
  if (r.console.size() < 3) return {};
  std::vector<std::string> out;
  std::string all;
  for (std::size_t k = 3; k < r.console.size(); ++k) all += r.console[k];
  std::size_t from = 0;
  for (std::size_t at; (at = all.find("\r\n", from)) != std::string::npos; from = at + 2) {
    out.push_back(all.substr(from, at - from));
  }
  return out;
}

TEST(EngineMcdrive, ObjectsReturnsAndErrors) {
  EngineRig r;
  const auto out = lines_of(r,
                            "import mcdrive as mc\nimport mcdrive\nimport drive\n"
                            "print(mc is mcdrive and mc is drive)\n"
                            "print(mc.WriteObject(0x6081, 0, -2))\n"
                            "print(mc.ReadObject(0x6081, 0))\n"
                            "print(mc.WriteObject(0x6041, 0, 5))\n"
                            "print(mc.ReadObject(0x1008, 0))\n"
                            "try:\n    mc.WriteObject(0x6081, 0, 2**31)\nexcept OverflowError as e:\n    print(e)\n"
                            "try:\n    mc.SetAcc('5')\nexcept TypeError as e:\n    print(e)\n"
                            "try:\n    mc.GoPosAbs(targetPos=5)\nexcept TypeError as e:\n    print(e)\n"
                            "try:\n    mc.ReadObject(1)\nexcept TypeError as e:\n    print(e)\n"
                            "print(mc.WriteObject(0x6083, 0, True))\n"
                            "try:\n    mc.NoSuch()\nexcept AttributeError as e:\n    print(e)\n");
  EXPECT_EQ(out, (std::vector<std::string>{"True", "0", "-2", "100728834", "101122064",
                                           "overflow converting long int to machine word", "can't convert str to int",
                                           "function does not take keyword arguments",
                                           "function takes 2 positional arguments but 1 were given", "0",
                                           "'module' object has no attribute 'NoSuch'"}));
  EXPECT_EQ(r.get(0x6081), 4294967294LL);
  EXPECT_EQ(r.get(0x6083), 1);
}

TEST(EngineMcdrive, GoPosAbsFromSodAndWaitForReady) {
  EngineRig r;
  const auto out = lines_of(r,
                            "import mcdrive as mc\nimport sys\n"
                            "mc.GoPosAbs(1000)\n"
                            "print(mc.ChkMoving(), mc.ChkReady())\n"
                            "while mc.ChkReady() == 0:\n    sys.wait(1)\n"
                            "print(mc.GetActualPos(), mc.ChkEnabled())\n"
                            "mc.PowerQuit()\nprint(mc.ChkEnabled(), mc.GetOpMode())\n");
  EXPECT_EQ(out, (std::vector<std::string>{"1 0", "1000 1", "0 0"}));
}

TEST(EngineMcdrive, StorePermanentReturnsWhenComplete) {
  EngineRig r;
  r.fixture.release_store_hooks();  // this test's hook stands in for the persistence service
  od::Done pending;
  r.od.on_write(0x1010, 1, [&](od::WriteRequest& req) {
    pending = std::move(*req.done);
    return od::AbortCode::pending;
  });
  r.start("import mcdrive as mc\nmc.StorePermanent()\nprint('stored')\n");
  r.advance(300);
  EXPECT_EQ(r.text().find("stored"), std::string::npos);  // still waiting for the file
  ASSERT_TRUE(pending);
  pending(od::AbortCode::none);
  ASSERT_TRUE(r.wait([&] { return r.text().find("stored") != std::string::npos; }));
  r.od.on_write(0x1010, 1, {});
}

TEST(EngineMcdrive, ResetToFactoryRefusedInOeReturns) {
  EngineRig r;
  const auto out = lines_of(r, "import mcdrive as mc\nmc.EnableDrive()\nmc.ResetToFactory()\nprint('back')\n");
  EXPECT_EQ(out, (std::vector<std::string>{"back"}));
}

TEST(EngineMcdrive, SetOutAndChkIn) {
  EngineRig r;
  const auto out = lines_of(r,
                            "import mcdrive as mc\nmc.SetOut(1)\nprint(mc.ReadObject(0x60fe, 1))\nmc.ClearOut(1)\n"
                            "mc.WriteObject(0x3510, 1, 0x10000)\nprint(mc.ChkIn(1), mc.ChkIn(2))\n");
  EXPECT_EQ(out, (std::vector<std::string>{"65536", "1 0"}));
}

TEST(EngineRefgo, CmdReturnTypes) {
  EngineRig r;
  const auto out = lines_of(r,
                            "import refgo\nprint(refgo.cmd('TS'), refgo.cmd('tp'), refgo.cmd('TPSR'))\n"
                            "print(repr(refgo.cmd('OW6091,1,1')), repr(refgo.cmd('SP720')), refgo.cmd('XYZ'))\n");
  ASSERT_EQ(out.size(), 2U);
  EXPECT_EQ(out[1], "'OW6091,1,1,OK' '' None");
  EXPECT_EQ(out[0].substr(0, 4), "0 0 ");
}

TEST(EngineRefgo, TtTvExtensionInModeTwo) {  // refgo.md §14.3 with a script of our own
  EngineRig r;
  refgo::Session client(r.in);
  r.start(
      "import time\nimport refgo\nimport mcdrive as mc\nrefgo.open(2)\n"
      "while True:\n"
      "    cmd = refgo.read()\n"
      "    if cmd is not None:\n"
      "        if cmd == 'TT':\n"
      "            refgo.write('TT\\r\\n' + repr(mc.ReadObject(0x3401, 0x0a)) + '\\r\\n>')\n"
      "        elif cmd == 'TV':\n"
      "            refgo.write('TV\\r\\n' + repr(mc.ReadObject(0x606c, 0)) + '\\r\\n>')\n"
      "    time.sleep_ms(5)\n");
  r.advance(200);
  ASSERT_TRUE(r.in.attachment().attached());
  client.receive("TT\r");
  EXPECT_EQ(client.take_output(), "");
  std::string got;
  ASSERT_TRUE(r.advance_until([&] { return (got += client.take_output()).find('>') != std::string::npos; }, 100));
  EXPECT_EQ(got, "TT\r\n" + std::to_string(r.read(0x3401, 0x0A)) + "\r\n>");
  client.receive("TS\r");  // known: the built-in interpreter answers
  EXPECT_EQ(client.take_output(), "TS\r\n0\r\n>");
  r.engine->stop();
  EXPECT_FALSE(r.in.attachment().attached());  // detached on stop
  client.receive("TT\r");
  EXPECT_EQ(client.take_output(), ">");
}

TEST(EngineRefgo, LegacyEvtScriptInModeTwo) {  // scripting.md §12 refGoExtensionExampleEvt row
  EngineRig r;
  refgo::Session client(r.in);
  r.start(
      "import sys\nimport refgo\nevt = 0\nold = -1\nrefgo.open('refgo', 0)\n"
      "while 1:\n"
      "    cmd = refgo.read(0, 0)\n"
      "    if cmd is not None:\n"
      "        if cmd == 'EVT1':\n"
      "            evt = 1\n"
      "            refgo.write(0, 0, '@H\\r\\n')\n"
      "        elif cmd == 'EVT0':\n"
      "            evt = 0\n"
      "            old = -1\n"
      "        refgo.write(0, 0, '>')\n"
      "    if evt == 1:\n"
      "        ts = refgo.cmd('TS')\n"
      "        if ts is not None and ts != old:\n"
      "            old = ts\n"
      "            refgo.write(0, 0, '@S' + str(ts) + '\\r\\n>')\n"
      "    sys.wait(1)\n");
  r.advance(200);
  client.receive("EVT1\r");
  std::string got;
  ASSERT_TRUE(r.advance_until([&] { return (got += client.take_output()).find("@S0\r\n>") != std::string::npos; }, 50));
  EXPECT_EQ(got, "@H\r\n>@S0\r\n>");
  got.clear();
  client.receive("G5000\r");
  got += client.take_output();
  EXPECT_EQ(got.substr(0, 8), "G5000\r\n>");
  ASSERT_TRUE(
      r.advance_until([&] { return (got += client.take_output()).find("@S1\r\n>") != std::string::npos; }, 20000));
  EXPECT_NE(got.find("@S2\r\n>"), std::string::npos);
  got.clear();
  client.receive("EVT0\r");
  ASSERT_TRUE(r.advance_until([&] { return (got += client.take_output()) == ">"; }, 50));
  r.engine->stop();
}

TEST(EngineRefgo, ScriptOnlyModeAndWriteTargets) {
  EngineRig r;
  refgo::Session a(r.in);
  refgo::Session b(r.in);
  r.start(
      "import refgo\nimport time\nrefgo.open(3)\nprint(refgo.write('hello'))\n"
      "while True:\n    l = refgo.read()\n    if l is not None:\n        print(refgo.write('<' + l + '>'))\n"
      "    time.sleep_ms(1)\n");
  r.advance(200);
  EXPECT_EQ(a.take_output(), "hello");  // before the first read: every client
  EXPECT_EQ(b.take_output(), "hello");
  b.receive("g1000\r");  // mode 3: not executed, original case
  ASSERT_TRUE(r.advance_until([&] { return b.take_output() == "<g1000>"; }, 50));
  EXPECT_EQ(a.take_output(), "");
  EXPECT_EQ(r.get(0x607A), 0);
  r.engine->stop();
}

TEST(EngineTime, TicksWrapCycleTimeAndMissingNames) {
  EngineRig r;
  const auto out = lines_of(r,
                            "import time\nimport utime\nimport sys\n"
                            "print(time is utime, time.ticks_diff(5, 2**30 - 5), time.ticks_add(2**30 - 1, 2))\n"
                            "print(time.ticks_diff(2**30 - 5, 5))\n"
                            "try:\n    time.time()\nexcept AttributeError as e:\n    print(e)\n"
                            "t0 = time.ticks_ms()\nsys.cycle_time_ms(0)\n"
                            "print(sys.cycle_time_ms(10), time.ticks_diff(time.ticks_ms(), t0))\n"
                            "time.sleep_ms(25)\nprint(sys.cycle_time_ms(10))\n"
                            "print(sys.time() == time.ticks_ms(), time.ticks_us() // 1000 == time.ticks_ms())\n"
                            "time.sleep_us(1)\ntime.sleep(1)\nprint(time.ticks_diff(time.ticks_ms(), t0))\n");
  EXPECT_EQ(out, (std::vector<std::string>{"True 10 1", "-10", "'module' object has no attribute 'time'", "10 10",
                                           "-15", "True True", "1036"}));
}

TEST(EngineSys, ModuleValues) {
  EngineRig r;
  const auto out =
      lines_of(r,
               "import sys\nprint(sys.version, sys.version_info, sys.platform, sys.byteorder, sys.maxsize)\n"
               "print(sys.implementation.name, sys.implementation.version, sys.implementation.platver)\n"
               "print(repr(sys.stdin.read()), sys.argv, sys.path)\n"
               "try:\n    raise KeyError('k')\nexcept KeyError as e:\n    sys.print_exception(e)\n"
               "    print(sys.exc_info()[0] is KeyError)\n"
               "import gc, micropython\nprint(gc.mem_free(), micropython.const(7), const(8))\n"
               "sys.stdout.write('w\\n')\nsys.exit()\nprint('never')\n");
  ASSERT_EQ(out.size(), 9U);
  EXPECT_EQ(out[0], "3.4.0 (3, 4, 0) movingcap little 2147483647");
  EXPECT_EQ(out[1].substr(0, 23), "micropython (1, 9, 4) (");
  EXPECT_EQ(out[2], "'' [] []");
  EXPECT_EQ(out[3], "Traceback (most recent call last):");
  EXPECT_EQ(out[4], "  File \"<stdin>\", line 6, in <module>");
  EXPECT_EQ(out[5], "KeyError: k");
  EXPECT_EQ(out[6], "True");
  EXPECT_EQ(out[7], "65536 7 8");
  EXPECT_EQ(out[8], "w");
}

TEST(EngineStrict, FloatsFailAndPassWithStrictOff) {
  EngineRig r;
  ASSERT_TRUE(r.run("x = 1\ny = 1.5\n"));
  EXPECT_NE(r.text().find("  File \"<stdin>\", line 2\r\nSyntaxError: decimal numbers not supported\r\n"),
            std::string::npos);
  ASSERT_TRUE(r.run("import os\n"));
  EXPECT_NE(r.text().find("ImportError: no module named 'os'\r\n"), std::string::npos);
  r.engine->set_strict(false);
  const auto out = lines_of(r, "x = 7 / 2\nprint(x)\nimport os\nprint(os.getcwd() != '')\n");
  EXPECT_EQ(out, (std::vector<std::string>{"3.5", "True"}));
}

TEST(EngineStrict, TabsAsMicroPythonCountsThem) {  // scripting.md §13.3
  EngineRig r;
  const auto out = lines_of(r, "if 1:\n\tx = 1\n        y = 2\nprint(x + y)\n");
  EXPECT_EQ(out, (std::vector<std::string>{"3"}));
}

TEST(EngineStrict, NegativeTest3LineFlatTrackRunAndIo) {  // §12 last row of group 1
  EngineRig r("MCFLAT");
  ASSERT_TRUE(r.run("#id our own negative test\nimport sys\nimport mcdrive a drive\n\nprint(1)\n"));
  EXPECT_NE(r.text().find("  File \"<stdin>\", line 3\r\nSyntaxError: invalid syntax\r\n"), std::string::npos);
  EXPECT_EQ(r.engine->state(), RunState::off);
}

TEST(EngineOutput, PartialLineAfter50msAndOrderWithMoves) {
  EngineRig r;
  r.start(
      "import time\nimport mcdrive as mc\nprint('x', end='')\ntime.sleep_ms(200)\nprint('before')\n"
      "mc.GoPosAbs(100)\ntime.sleep_ms(200)\n");
  const std::uint64_t t0 = r.core.time_ms();
  std::uint64_t seen = 0;
  ASSERT_TRUE(r.advance_until(
      [&] {
        if (r.console.size() > 3 && !seen) seen = r.core.time_ms();
        return seen != 0;
      },
      1000));
  EXPECT_EQ(r.console[3], "x");
  EXPECT_EQ(seen - t0, 150U);  // 100 ms to compile, then 50 ms
  ASSERT_TRUE(r.advance_until([&] { return r.engine->state() == RunState::off; }, 1000));
  EXPECT_EQ(r.console[4], "before\r\n");
}

}  // namespace
}  // namespace mcemu::scripting::test
