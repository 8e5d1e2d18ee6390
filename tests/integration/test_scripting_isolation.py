"""Isolation of MovingCap CODE scripts over the real binary (scripting.md §10.1, §13 item 9): a
script that spins, recurses without end, asks for gigabytes, prints without end or exits the engine
never stops the emulator — RefGo, HTTP and the WebSocket keep answering while it runs, and the
engine's state ends as specified. Behaviour only: the latency, rate and stop-time numbers are
measured by bench/ (design.md: tests never assert on wall-clock speed).
"""
import json
import os
import tempfile
import time
import unittest

from mcemu_harness import SANITIZED, Mcemu, wait_for
from script_client import RefGo, UdpConsole
from ws_client import WebSocket


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def children(pid):
    """The pids of the processes whose parent is `pid` (the script engine's python3)."""
    out = []
    for task in os.listdir("/proc/%d/task" % pid):
        try:
            with open("/proc/%d/task/%s/children" % (pid, task)) as f:
                out += [int(p) for p in f.read().split()]
        except FileNotFoundError:
            pass
    return out


class Isolation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # docs/security.md: scriptStrict false over HTTP only where the config file allowed it at start
        with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="iso-", delete=False) as f:
            json.dump({"settings": {"scriptStrict": False}}, f)
        cls.config = f.name
        cls.m = Mcemu("--config", cls.config)
        cls.pid = cls.m.proc.pid

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)
        os.unlink(cls.config)

    def setUp(self):
        self.m.http("PUT", "/api/v1/settings", {"scriptStrict": True})  # each test starts strict
        self.udp = UdpConsole(self.m.ports["udp"])
        self.rg = RefGo(self.m.ports["refgo"])
        self.ws = WebSocket(self.m.ports["http"])
        self.assertEqual(self.ws.recv_json()["type"], "hello")

    def tearDown(self):
        self.m.http("POST", "/api/v1/script/stop", {})
        self.m.http("PUT", "/api/v1/settings", {"scriptStrict": True})
        self.ws.close()
        self.rg.close()
        self.udp.close()

    def view(self):
        status, body = self.m.http("GET", "/api/v1/script")
        self.assertEqual(status, 200)
        return json.loads(body)

    def start(self, source):
        mark = self.udp.mark()
        status, _ = self.m.http("PUT", "/api/v1/script", source, content_type="text/x-python")
        self.assertEqual(status, 200)
        self.udp.wait_for(b"code: upload complete", mark)
        mark = self.udp.mark()
        status, _ = self.m.http("POST", "/api/v1/script/start", {})
        self.assertEqual(status, 200)
        self.udp.wait_for(b"code: execute, script id: ", mark)
        return mark

    def assert_emulator_answers(self, seconds=1.0):
        """RefGo, HTTP and the WebSocket status stream all keep answering for `seconds`."""
        deadline = time.monotonic() + seconds
        polls = 0
        while time.monotonic() < deadline:
            self.assertRegex(self.rg.request("TP", timeout=5), rb"^TP\r\n-?[0-9]+\r\n>$")
            polls += 1
        self.assertGreater(polls, 0)
        status, body = self.m.http("GET", "/api/v1/status", timeout=5)
        self.assertEqual(status, 200)
        self.assertIn("python", json.loads(body))
        statuses = 0
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:
            if self.ws.recv_json(timeout=2)["type"] == "status":
                statuses += 1
        self.assertGreaterEqual(statuses, 3, "the WebSocket status stream keeps coming (20 Hz nominal)")

    def assert_no_engine_left(self):
        wait_for(lambda: not children(self.pid), timeout=10, what="the engine process reaped")

    def test_spinning_script_keeps_running_until_stopped(self):
        rss = rss_kib(self.pid)
        self.start(b"#id spin\nwhile True:\n    pass\n")
        self.assert_emulator_answers()
        self.assertEqual(self.view()["state"], "RUN")
        wait_for(lambda: self.view()["line"] in (2, 3), what="the current line sampled in a tight loop")
        status, _ = self.m.http("POST", "/api/v1/script/stop", {})
        self.assertEqual(status, 200)
        self.assertEqual(self.view()["state"], "OFF", "a stop is at once, also in a tight loop")
        self.assert_no_engine_left()
        if not SANITIZED:
            self.assertLess(rss_kib(self.pid) - rss, 5 * 1024)

    def test_deep_recursion_ends_with_the_micropython_error(self):
        mark = self.start(b"#id deep\ndef f(n):\n    return f(n + 1)\nf(0)\n")
        self.udp.wait_for(b"RuntimeError: maximum recursion depth exceeded\r\n", mark)
        wait_for(lambda: self.view()["state"] == "OFF", what="OFF after the traceback")
        self.assertIn(b"Traceback (most recent call last):\r\n  File \"<stdin>\", line 4, in <module>\r\n"
                      b"  File \"<stdin>\", line 3, in f\r\n", self.udp.text(mark))
        self.assert_emulator_answers(0.3)
        self.assert_no_engine_left()

    def test_memory_hog_gets_memory_error(self):
        rss = rss_kib(self.pid)
        mark = self.start(b"#id hog\nprint('asking')\nx = [0] * 10**9\nprint('never')\n")
        self.udp.wait_for(b"MemoryError: \r\n", mark)
        wait_for(lambda: self.view()["state"] == "OFF", what="OFF after the MemoryError")
        text = self.udp.text(mark)
        self.assertIn(b"asking\r\nTraceback (most recent call last):\r\n  File \"<stdin>\", line 3, in <module>\r\n"
                      b"MemoryError: \r\n", text)
        self.assertNotIn(b"never", text)
        self.assertEqual(self.view()["line"], 3)
        self.assert_emulator_answers(0.3)
        if not SANITIZED:
            self.assertLess(rss_kib(self.pid) - rss, 5 * 1024, "the emulator's own memory does not grow")
        self.assert_no_engine_left()

    def test_endless_print_is_slowed_not_the_emulator(self):
        # Every console datagram is a trace event (web.md §8.6), and the bounded 10 000-event ring holds
        # ~12 MiB of these 1 KB lines once full: the baseline is taken while the script prints, after
        # the ring has turned over once, and the growth is measured over a second turn-over.
        def turned_over(since):
            return json.loads(self.m.http("GET", f"/api/v1/trace?since={since}&limit=1")[1])["dropped"] > 0

        def next_seq():
            return json.loads(self.m.http("GET", "/api/v1/trace?limit=1")[1])["nextSeq"]

        first = next_seq()
        mark = self.start(b"#id chatter\nwhile True:\n    print('x' * 1000)\n")
        self.udp.wait_for(b"x" * 1000 + b"\r\n", mark)
        wait_for(lambda: turned_over(first), timeout=60, what="a trace ring of only the chatter's lines")
        rss, second = rss_kib(self.pid), next_seq()
        wait_for(lambda: turned_over(second), timeout=60, what="a second turn-over of the trace ring")
        grown = rss_kib(self.pid) - rss
        self.assert_emulator_answers()
        self.assertEqual(self.view()["state"], "RUN")
        status, _ = self.m.http("POST", "/api/v1/script/stop", {})
        self.assertEqual(self.view()["state"], "OFF")
        self.assert_no_engine_left()
        if not SANITIZED:
            self.assertLess(grown, 5 * 1024, "10 000 more lines printed: the emulator's memory does not grow")

    def test_engine_exit_is_an_engine_failure(self):
        status, _ = self.m.http("PUT", "/api/v1/settings", {"scriptStrict": False})
        self.assertEqual(status, 200)
        mark = self.start(b"#id quitter\nimport os\nprint('bye')\nos._exit(3)\n")
        self.udp.wait_for(b"code: engine failure (exit status 3), script id: quitter\n\r", mark)
        self.assertIn(b"bye\r\ncode: engine failure", self.udp.text(mark), "its output first, in order")
        wait_for(lambda: self.view()["state"] == "OFF", what="OFF after the engine died")
        self.assert_emulator_answers(0.3)
        self.assert_no_engine_left()

    def test_strict_mode_refuses_os(self):
        mark = self.start(b"#id strict\nimport os\n")
        self.udp.wait_for(b"ImportError: no module named 'os'\r\n", mark)
        wait_for(lambda: self.view()["state"] == "OFF", what="OFF")


if __name__ == "__main__":
    unittest.main()
