"""MovingCap CODE over the real mcemu binary (issue 14; scripting.md §3, web.md §6, §8.7, §9,
udp-debug.md §4.2–§4.6, refgo.md §5, persistence.md §7).

The scripts are the tests' own texts (third-party example code is not committed, refgo.md §15).
Uploads and starts go through the same bytes Fullmo's uploader sends (script_client.py). Every wait
polls with a bound; the real clock is used except where a test says otherwise.
"""
import json
import os
import re
import tempfile
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from script_client import MODE3_ECHO, RefGo, UdpConsole, code_act, exchange, get_request, upload_script

ID = b"maxTRACK N23 demo rev8"  # udp-debug.md §7: the id of the DLU recordings


def script_view(m):
    status, body = m.http("GET", "/api/v1/script")
    assert status == 200, (status, body)
    return json.loads(body)


def wait_state(m, state, timeout=10.0):
    return wait_for(lambda: script_view(m)["state"] == state, timeout=timeout, what="script state " + state)


def non_strict_config():
    """A config file whose "settings" start scriptStrict false: only then may PUT /api/v1/settings
    switch it off (docs/security.md). The caller removes the file."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="scr-", delete=False) as f:
        json.dump({"settings": {"scriptStrict": False}}, f)
    return f.name


def put_script(m, text):
    status, body = m.http("PUT", "/api/v1/script", text if isinstance(text, bytes) else text.encode(),
                          content_type="text/x-python")
    assert status == 200, (status, body)
    return json.loads(body)


class Uploader(unittest.TestCase):
    """web.md §6 and §11: a client that sends what UPL sends, and the answers UPL checks."""

    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu()
        cls.http = cls.m.ports["http"]

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def setUp(self):
        self.udp = UdpConsole(self.m.ports["udp"])

    def tearDown(self):
        code_act(self.http, 4)
        self.udp.close()

    def test_upload_start_stop_as_fullmos_uploader(self):
        source = b"#id " + ID + b"\r\nimport sys\r\nprint(\"Hello World from MovingCap!\")\r\nwhile True:\r\n" \
                 b"    sys.wait(20)\r\n"
        mark = self.udp.mark()
        ok, (status, headers, body) = upload_script(self.http, source, "demo.py")
        self.assertTrue(ok, status)
        self.assertEqual(headers["content-type"], "text/html; charset=utf-8")
        self.assertIn(b'name="Python script file for MovingCap CODE"', body, "the Code page")
        self.udp.wait_for(b"code: upload complete, script id: " + ID + b"\r\n", mark)
        self.assertEqual(self.udp.text(mark),
                         b"code: starting upload...\r\ncode: upload complete, script id: " + ID + b"\r\n")
        view = script_view(self.m)
        self.assertEqual((view["id"], view["state"], view["length"]), (ID.decode(), "OFF", len(source)))
        self.assertEqual(self.m.read_object(0x3500, 5), len(source))
        self.assertEqual(view["source"], source.decode(), "stored byte for byte (CRLF kept)")
        # UPL start_script(): codeAct=3, 200; udp-debug.md §7.2
        mark = self.udp.mark()
        ok, (status, _, _) = code_act(self.http, 3)
        self.assertTrue(ok, status)
        expected = (b"code: starting, script id: " + ID + b"\n\r" + b"code: compile, script id: " + ID + b"\n\r" +
                    b"code: execute, script id: " + ID + b"\n\r" + b"Hello World from MovingCap!\r\n")
        self.udp.wait_for(b"Hello World from MovingCap!\r\n", mark)
        self.assertEqual(self.udp.text(mark), expected)
        self.assertEqual(script_view(self.m)["state"], "RUN")
        self.assertEqual(self.m.read_object(0x3500, 2), 1)
        status, body = self.m.http("GET", "/api/v1/status")
        self.assertEqual(json.loads(body)["footer"]["python"], "Python RUN")
        # UPL stop_script(): codeAct=4, 200; no UDP line (udp-debug.md §4.3)
        mark = self.udp.mark()
        ok, (status, _, _) = code_act(self.http, 4)
        self.assertTrue(ok, status)
        self.assertEqual(script_view(self.m)["state"], "OFF", "a stop takes effect at once")
        self.assertEqual(self.m.read_object(0x3500, 2), 0)
        self.udp.poll(0.2)
        self.assertEqual(self.udp.text(mark), b"")

    def test_refused_uploads(self):
        before = script_view(self.m)
        ok, (status, _, body) = upload_script(self.http, b"")
        self.assertEqual(status, 400)
        ok, (status, _, body) = upload_script(self.http, b"#" * 65537)
        self.assertEqual(status, 413)
        self.assertIn(b"larger than 65536", body)
        # the wrong field name
        from script_client import requests_multipart
        body, ctype = requests_multipart("file", "x.py", b"print(1)\n")
        status, _, _ = exchange(self.http, b"POST /program.html HTTP/1.1\r\nHost: x\r\nContent-Length: " +
                                str(len(body)).encode() + b"\r\nContent-Type: " + ctype.encode() + b"\r\n\r\n" + body)
        self.assertEqual(status, 400)
        self.assertEqual(script_view(self.m), before, "nothing changed")
        ok, (status, _, _) = upload_script(self.http, b"#" * 65536)
        self.assertEqual(status, 200, "65 536 bytes are accepted")

    def test_cross_site_requests_are_refused(self):
        # web.md §1.3 and §11: a cross-site Origin on both endpoints gets 403 and changes nothing
        put_script(self.m, "#id before\nprint(1)\n")
        evil = b"Origin: http://evil.example\r\n"
        ok, (status, _, _) = upload_script(self.http, b"#id evil\nprint(2)\n", extra_headers=evil)
        self.assertEqual(status, 403)
        ok, (status, _, _) = code_act(self.http, 3, extra_headers=b"Sec-Fetch-Site: cross-site\r\n")
        self.assertEqual(status, 403)
        view = script_view(self.m)
        self.assertEqual((view["id"], view["state"]), ("before", "OFF"))
        # HEAD never acts (web.md §1.4)
        status, _, _ = exchange(self.http, b"HEAD /program.html?codeAct=3 HTTP/1.1\r\nHost: x\r\n\r\n", head=True)
        self.assertEqual(status, 200)
        self.assertEqual(script_view(self.m)["state"], "OFF")

    def test_code_act_pause_resume_autostart(self):
        put_script(self.m, "#id loop\nimport sys\nwhile True:\n    sys.wait(10)\n")
        self.assertTrue(code_act(self.http, 3)[0])
        wait_for(lambda: script_view(self.m)["line"] > 0, what="the current line sample")
        self.assertTrue(code_act(self.http, 1)[0])
        self.assertEqual(script_view(self.m)["state"], "BRK")
        self.assertEqual(self.m.read_object(0x3500, 2), 2)
        self.assertTrue(code_act(self.http, 2)[0])
        self.assertEqual(script_view(self.m)["state"], "RUN")
        self.assertTrue(code_act(self.http, 5)[0])
        self.assertEqual(self.m.read_object(0x3500, 4), 1)
        status, body = self.m.http("GET", "/api/v1/status")
        self.assertEqual(json.loads(body)["footer"]["python"], "Python RUN/A")
        self.assertTrue(code_act(self.http, 6)[0])
        self.assertEqual(self.m.read_object(0x3500, 4), 0)
        for other in (0, 7, 99):
            self.assertTrue(code_act(self.http, other)[0])
        status, _, _ = exchange(self.http, get_request("127.0.0.1", "/program.html?codeAct=abc"))
        self.assertEqual(status, 200)
        self.assertEqual(script_view(self.m)["state"], "RUN", "ignored values change nothing")


class Output(unittest.TestCase):
    """udp-debug.md §4.3–§4.6 byte for byte, and the script state each time."""

    @classmethod
    def setUpClass(cls):
        # docs/security.md: scriptStrict false over HTTP only where the config file allowed it at start
        cls.config = non_strict_config()
        cls.m = Mcemu("--config", cls.config)

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)
        os.unlink(cls.config)

    def setUp(self):
        self.udp = UdpConsole(self.m.ports["udp"])
        self.m.http("PUT", "/api/v1/settings", {"scriptStrict": True})  # each test starts strict

    def tearDown(self):
        self.m.http("POST", "/api/v1/script/stop", {})
        self.udp.close()

    def run_script(self, text, until, state="OFF"):
        mark = self.udp.mark()
        put_script(self.m, text)
        self.udp.wait_for(b"code: upload complete", mark)  # delivered before the start's lines
        mark = self.udp.mark()
        status, _ = self.m.http("POST", "/api/v1/script/start", {})
        self.assertEqual(status, 200)
        self.udp.wait_for(until, mark)
        wait_state(self.m, state)
        return self.udp.text(mark)

    def test_compile_error_7_3(self):
        text = b"#id " + ID + b"\n" + b"x = 1\n" * 20 + b" x = 2\n"
        out = self.run_script(text, b"IndentationError: unexpected indent\r\n")
        self.assertEqual(out, b"code: starting, script id: " + ID + b"\n\r" + b"code: compile, script id: " + ID +
                         b"\n\r" + b"Traceback (most recent call last):\r\n" + b"  File \"<stdin>\", line 22\r\n" +
                         b"IndentationError: unexpected indent\r\n")
        self.assertEqual(self.m.read_object(0x3500, 2), 0)
        self.assertEqual(self.m.read_object(0x3500, 3), 22)

    def test_runtime_traceback_7_4(self):
        out = self.run_script(b"def f():\n    return 1 // 0\nf()\n", b"ZeroDivisionError: division by zero\r\n")
        self.assertTrue(out.endswith(b"code: execute, script id: (empty)\n\r" + b"Traceback (most recent call last):\r\n"
                                     b"  File \"<stdin>\", line 3, in <module>\r\n"
                                     b"  File \"<stdin>\", line 2, in f\r\n"
                                     b"ZeroDivisionError: division by zero\r\n"), out)
        self.assertEqual(self.m.read_object(0x3500, 3), 2)

    def test_strict_mode_and_its_setting(self):
        out = self.run_script(b"#id f\nx = 1\ny = 2.5\n", b"SyntaxError: decimal numbers not supported\r\n")
        self.assertIn(b"  File \"<stdin>\", line 3\r\n", out)
        status, _ = self.m.http("PUT", "/api/v1/settings", {"scriptStrict": False})
        self.assertEqual(status, 200)
        try:
            out = self.run_script(b"#id f\nprint(7 / 2)\n", b"3.5\r\n")
            self.assertTrue(out.endswith(b"code: execute, script id: f\n\r3.5\r\n"), out)
        finally:
            self.m.http("PUT", "/api/v1/settings", {"scriptStrict": True})

    def test_partial_line_50_ms_rule_and_crlf(self):
        # udp-debug.md §4.4: every \n → \r\n; a held partial line is its own message after 50 ms
        out = self.run_script(b"import sys\nprint('a\\r\\nb')\nprint('x', end='')\nsys.wait(200)\nprint('y')\n",
                              b"y\r\n")
        self.assertIn(b"a\r\r\nb\r\nxy\r\n", out, "\\n after \\r becomes \\r\\n too")
        tail = [d for d in self.udp.datagrams if d in (b"x", b"y\r\n")]
        self.assertEqual(tail[-2:], [b"x", b"y\r\n"], "x held, then sent alone after 50 ms; y later")

    def test_memory_setting_applies_from_the_next_start(self):
        hog = b"#id mem\nx = [0] * (16 * 1024 * 1024)\nprint('got it')\n"  # 128 MiB of references
        status, _ = self.m.http("PUT", "/api/v1/settings", {"scriptMemoryMiB": 64})
        self.assertEqual(status, 200)
        try:
            out = self.run_script(hog, b"MemoryError: \r\n")
            self.assertNotIn(b"got it", out)
        finally:
            self.m.http("PUT", "/api/v1/settings", {"scriptMemoryMiB": 256})
        self.run_script(hog, b"got it\r\n")

    def test_trace_of_calls_and_state_changes(self):
        status, _ = self.m.http("PUT", "/api/v1/settings", {"traceScriptCalls": True})
        self.assertEqual(status, 200)
        try:
            self.run_script(b"#id traced\nimport mcdrive as mc\nprint(mc.ReadObject(0x6041, 0))\n", b"\r\n")
        finally:
            self.m.http("PUT", "/api/v1/settings", {"traceScriptCalls": False})
        status, body = self.m.http("GET", "/api/v1/trace?channels=script&limit=10000")
        texts = [e["text"] for e in json.loads(body)["events"]]
        self.assertIn("state RUN, script id: traced", texts)
        self.assertIn("state OFF, script id: traced", texts)
        self.assertTrue(any(re.fullmatch(r"mcdrive\.ReadObject\(24641, 0\) -> [0-9]+", t) for t in texts), texts)

    def test_script_kill_fault_4_6(self):
        put_script(self.m, "#id victim\nimport sys\nwhile True:\n    sys.wait(10)\n")
        self.m.http("POST", "/api/v1/script/start", {})
        wait_state(self.m, "RUN")
        mark = self.udp.mark()
        self.udp.wait_for(b"code: execute, script id: victim\n\r", 0)
        status, body = self.m.http("POST", "/api/v1/faults", {"kind": "script.kill"})
        self.assertEqual(status, 201, body)
        self.udp.wait_for(b"code: engine failure (signal 9), script id: victim\n\r", mark)
        wait_state(self.m, "OFF")
        self.assertEqual(self.m.read_object(0x3500, 2), 0)
        status, body = self.m.http("POST", "/api/v1/faults", {"kind": "script.kill"})
        self.assertEqual(status, 409, body)
        self.assertEqual(json.loads(body)["error"]["code"], "conflict")

    def test_print_exception_and_exit(self):
        out = self.run_script(b"import sys\ntry:\n    raise ValueError\nexcept ValueError as e:\n"
                              b"    sys.print_exception(e)\nprint('after')\nsys.exit()\nprint('never')\n",
                              b"after\r\n")
        self.assertIn(b"Traceback (most recent call last):\r\n  File \"<stdin>\", line 3, in <module>\r\n"
                      b"ValueError: \r\nafter\r\n", out)
        self.udp.poll(0.2)
        self.assertNotIn(b"never", self.udp.text())

    def test_self_stop_through_3500h_02(self):
        self.run_script(b"import mcdrive as mc\nprint('before')\nmc.WriteObject(0x3500, 2, 0)\nprint('after')\n",
                        b"before\r\n")
        self.udp.poll(0.2)
        self.assertNotIn(b"after", self.udp.text(), "a call that stops its own script does not return")


class Drive(unittest.TestCase):
    """A script moves the drive: observed over RefGo TP (scripting.md §5) while RefGo keeps working."""

    def test_script_moves_the_drive(self):
        with Mcemu() as m:
            udp = UdpConsole(m.ports["udp"])
            rg = RefGo(m.ports["refgo"])
            self.assertEqual(rg.tp(), 0)
            put_script(m, "#id mover\nimport mcdrive as mc\nimport sys\nmc.SetPosVel(2000)\nmc.GoPosAbs(1000)\n"
                          "while mc.ChkReady() == 0:\n    sys.wait(5)\nprint('at', mc.GetActualPos())\nsys.wait(300)\n"
                          "mc.GoPosRel(-300)\nwhile mc.ChkReady() == 0:\n    sys.wait(5)\n"
                          "print('at', mc.GetActualPos(), mc.ChkEnabled())\n")
            status, _ = m.http("POST", "/api/v1/script/start", {})
            self.assertEqual(status, 200)
            near = lambda p, target: abs(p - target) <= 3  # within the position window (6067h)
            seen = []
            deadline = time.monotonic() + 20
            while time.monotonic() < deadline and not (seen and near(seen[-1], 700) and
                                                       len(re.findall(rb"at [0-9 ]+\r\n", udp.text())) == 2):
                seen.append(rg.tp())  # RefGo answers while the script runs
                udp.poll(0.01)
            self.assertTrue(any(near(p, 1000) for p in seen), "the move to 1000 was seen over RefGo TP: %r" % seen)
            self.assertTrue(near(seen[-1], 700), seen)
            udp.wait_for(b" 1\r\n")
            lines = [l.split() for l in re.findall(rb"at [0-9 ]+\r\n", udp.text())]
            self.assertEqual(len(lines), 2, lines)
            self.assertTrue(near(int(lines[0][1]), 1000) and near(int(lines[1][1]), 700), lines)
            self.assertEqual(lines[1][2], b"1", "ChkEnabled")
            wait_state(m, "OFF")
            self.assertEqual(rg.request("TS"), b"TS\r\n1\r\n>", "stopping a script does not stop the drive")
            rg.close()
            udp.close()


TT_TV = b"""#id TT/TV extension (own text)
import mcdrive as mc
import refgo
import sys
refgo.open(2)
while True:
    line = refgo.read()
    if line is None:
        sys.wait(1)
        continue
    word = line.strip().upper()
    if word == "TT":
        refgo.write("TT\\r\\n" + str(mc.ReadObject(0x3401, 0x0A)) + "\\r\\n>")
    elif word == "TV":
        refgo.write("TV\\r\\n" + str(mc.ReadObject(0x606C, 0)) + "\\r\\n>")
"""

MODE3 = MODE3_ECHO


class Attachment(unittest.TestCase):
    """refgo.md §5 in the real server's RefGo sessions (§14.3 with a script of our own, §15.8)."""

    def test_modes_2_and_3_and_detach_on_stop(self):
        with Mcemu() as m:
            http = m.ports["http"]
            rg = RefGo(m.ports["refgo"])
            self.assertEqual(rg.request("TT"), b">", "no script: TT is an unknown word")
            temperature = rg.request("OR3401,0A").split(b"\r\n")[1].split(b",")[-1]
            self.assertTrue(upload_script(http, TT_TV, "tttv.py")[0])
            self.assertTrue(code_act(http, 3)[0])
            wait_for(lambda: json.loads(m.http("GET", "/api/v1/status")[1])["refgo"]["attachMode"] == 2,
                     what="attachment mode 2")
            self.assertEqual(rg.request("TT"), b"TT\r\n" + temperature + b"\r\n>", "written by the script alone")
            self.assertEqual(rg.request("TV"), b"TV\r\n0\r\n>")
            self.assertEqual(rg.request("TS"), b"TS\r\n0\r\n>", "known words: the built-in interpreter")
            # mode 3: every line goes to the script, the interpreter says nothing
            self.assertTrue(upload_script(http, MODE3, "mode3.py")[0])
            self.assertEqual(rg.request("TT"), b">", "the upload stopped the script: detached")
            self.assertTrue(code_act(http, 3)[0])
            wait_for(lambda: json.loads(m.http("GET", "/api/v1/status")[1])["refgo"]["attachMode"] == 3,
                     what="attachment mode 3")
            self.assertEqual(rg.request("TS"), b"[TS]>")
            self.assertEqual(rg.request("tp 1"), b"[tp 1]>", "original case and spaces")
            status, body = m.http("POST", "/api/v1/refgo", {"line": "TS"})
            self.assertEqual(json.loads(body)["reply"], "TS\r\n0\r\n>", "the API bypasses the script (§5.5)")
            self.assertTrue(code_act(http, 4)[0])
            self.assertEqual(rg.request("TS"), b"TS\r\n0\r\n>", "stopped: the built-in interpreter again")
            rg.close()


class PowerAndPersistence(unittest.TestCase):
    """persistence.md §4, §7: Store keeps the script, autostart after a power cycle only when
    stored, factory reset loads the placeholder."""

    LOOP = b"#id keeper\nimport sys\nprint('up')\nwhile True:\n    sys.wait(50)\n"

    def test_store_power_cycle_autostart_and_factory_reset(self):
        with Mcemu() as m:
            put_script(m, self.LOOP)
            self.assertEqual(m.write_object(0x3500, 4, 1)[0], 200)
            # not stored: a power cycle loads the stored script (the placeholder) and does not start
            status, _ = m.http("POST", "/api/v1/power-cycle", {})
            self.assertEqual(status, 200)
            view = script_view(m)
            self.assertEqual((view["id"], view["state"], view["length"]), ("(empty)", "OFF", 13))
            self.assertEqual(m.read_object(0x3500, 4), 0)
            # stored: the script and the flag survive, and it starts right after the start-up block
            put_script(m, self.LOOP)
            self.assertEqual(m.write_object(0x3500, 4, 1)[0], 200)
            self.assertEqual(m.store()[0], 200)
            status, _ = m.http("POST", "/api/v1/power-cycle", {})
            self.assertEqual(status, 200)
            self.assertEqual(script_view(m)["state"], "RUN", "autostart at power-up")
            udp = UdpConsole(m.ports["udp"])  # the power cycle forgot the listeners: the backlog
            udp.wait_for(b"up\r\n")
            self.assertTrue(udp.text().startswith(
                b"SYS_Initialize: The MPFS2 File System is mounted\r\n"), udp.text())
            # the registration's own echo and prompt come after the backlog, wherever that ends
            self.assertIn(b"REFGO - opening server\r\ncode: starting upload...\r\n"
                          b"code: upload complete, script id: keeper\r\n"
                          b"code: starting, script id: keeper\n\r"
                          b"code: compile, script id: keeper\n\r"
                          b"code: execute, script id: keeper\n\r"
                          b"up\r\n", udp.text().replace(b"\r>\r\n", b""))
            status, body = m.http("GET", "/api/v1/status")
            self.assertEqual(json.loads(body)["footer"]["python"], "Python RUN/A")
            # a Store while it runs does not affect it
            self.assertEqual(m.store()[0], 200)
            self.assertEqual(script_view(m)["state"], "RUN")
            # factory reset: stopped, the placeholder (scripting.md §2.3), autostart off
            status, body = m.http("POST", "/api/v1/factory-reset", {})
            self.assertEqual(status, 200, body)
            view = script_view(m)
            self.assertEqual((view["id"], view["state"], view["autostart"]), ("(empty)", "OFF", False))
            self.assertEqual((m.read_object(0x3500, 5), m.read_object(0x3500, 6)), (13, 0x23883CEF))
            self.assertEqual(m.read_object(0x3500, 1), "(empty)")
            udp.close()

    def test_script_survives_a_restart_of_the_process(self):
        with tempfile.TemporaryDirectory(prefix="scr2-") as tmp:
            state = os.path.join(tmp, "state")
            with Mcemu(state_dir=state) as m:
                put_script(m, self.LOOP)
                self.assertEqual(m.write_object(0x3500, 4, 1)[0], 200)
                self.assertEqual(m.store()[0], 200)
            with Mcemu(state_dir=state) as m:
                wait_state(m, "RUN")  # autostart at process start
                self.assertEqual(script_view(m)["id"], "keeper")
                self.assertEqual(script_view(m)["source"], self.LOOP.decode())


class NmtResetNode(unittest.TestCase):
    """scripting.md §3.2 / persistence.md §7: an NMT reset node terminates the engine, rebuilds the
    RAM image and starts the stored script if the stored autostart flag is set — no start-up block,
    the connections stay."""

    def test_reset_node_restarts_only_a_stored_autostart(self):
        from slcan_client import Raw
        with Mcemu() as m:
            udp = UdpConsole(m.ports["udp"])
            can = Raw(m.ports["slcan"])
            can.exchange(b"O\r", b"\r")

            def reset_node():  # NMT reset node to all nodes; frames are ignored until the boot-up
                can.send(b"t00028100\r")
                can.read_until(lambda b: b"t732100\r" in b)

            try:
                put_script(m, b"#id nmt\nimport sys\nprint('run')\nwhile True:\n    sys.wait(50)\n")
                self.assertEqual(m.write_object(0x3500, 4, 1)[0], 200)  # RAM only
                reset_node()
                view = script_view(m)
                self.assertEqual((view["id"], view["state"]), ("(empty)", "OFF"), "not stored: the placeholder")
                put_script(m, b"#id nmt\nimport sys\nprint('run')\nwhile True:\n    sys.wait(50)\n")
                self.assertEqual(m.write_object(0x3500, 4, 1)[0], 200)
                self.assertEqual(m.store()[0], 200)
                mark = udp.mark()
                reset_node()
                wait_state(m, "RUN")
                udp.wait_for(b"run\r\n", mark)
                text = udp.text(mark)
                self.assertEqual(text, b"code: starting, script id: nmt\n\rcode: compile, script id: nmt\n\r"
                                       b"code: execute, script id: nmt\n\rrun\r\n", "no start-up block")
                # while it runs: terminated and started again, the UDP listener kept
                mark = udp.mark()
                reset_node()
                udp.wait_for(b"run\r\n", mark)
                self.assertTrue(udp.text(mark).startswith(b"code: starting, script id: nmt\n\r"))
            finally:
                can.close()
                udp.close()


class EngineUnavailable(unittest.TestCase):
    """scripting.md §10.1.8 with a python3 that does not exist ("scripting.python" of --config)."""

    def test_everything_else_works(self):
        with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="scr2-", delete=False) as f:
            json.dump({"scripting": {"python": "/nonexistent/python3"}}, f)
        try:
            with Mcemu("--config", f.name) as m:
                info = json.loads(m.http("GET", "/api/v1/info")[1])
                wait_for(lambda: m.has_line("script engine unavailable: /nonexistent/python3"), what="the log line")
                self.assertFalse(info["scripting"]["available"])
                self.assertIsNone(info["scripting"]["engine"])
                self.assertIn("/nonexistent/python3", info["scripting"]["reason"])
                udp = UdpConsole(m.ports["udp"])
                ok, _ = upload_script(m.ports["http"], b"#id lonely\nprint(1)\n")
                self.assertTrue(ok, "uploads work")
                udp.wait_for(b"code: upload complete, script id: lonely\r\n")
                mark = udp.mark()
                self.assertTrue(code_act(m.ports["http"], 3)[0], "web.md §6.2: 200 also when unavailable")
                udp.wait_for(b"code: engine unavailable, script id: lonely\n\r", mark)
                self.assertEqual(udp.text(mark), b"code: starting, script id: lonely\n\r"
                                                 b"code: engine unavailable, script id: lonely\n\r")
                self.assertEqual(script_view(m)["state"], "OFF")
                status, body = m.http("POST", "/api/v1/script/start", {})
                self.assertEqual(status, 503)
                self.assertEqual(json.loads(body)["error"]["code"], "unavailable")
                rg = RefGo(m.ports["refgo"])
                self.assertEqual(rg.request("TS"), b"TS\r\n0\r\n>")
                rg.close()
                udp.close()
        finally:
            os.unlink(f.name)

    def test_bad_scripting_section_stops_start_up(self):
        with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="scr2-", delete=False) as f:
            json.dump({"scripting": {"pyhton": "/usr/bin/python3"}}, f)
        try:
            m = Mcemu("--config", f.name, ready=False)
            self.assertEqual(m.wait_exit(), 2)
            self.assertIn("scripting.pyhton", m.log())
        finally:
            os.unlink(f.name)


if __name__ == "__main__":
    unittest.main()
