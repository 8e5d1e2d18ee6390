"""The web platform against the real binary (issue 10's done-when): the WebSocket (hello, status
while eight RefGo clients poll, trace and udp subscriptions, origin check, client limit), the power
cycle of persistence.md §7 (stored values back, connections closed, UDP start-up block again) and
the two LEDs of morse-led.md §7 (schedule decode, live sampling under --clock manual, the +ERR text
of a fault, the yellow LED's connections)."""
import http.client
import json
import os
import re
import socket
import tempfile
import threading
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from mcemu_harness import refgo_line as refgo_exchange
from ws_client import HandshakeRefused, WebSocket

MORSE = {".-": "A", "-...": "B", "-.-.": "C", "-..": "D", ".": "E", "..-.": "F", "--.": "G", "....": "H",
         "..": "I", ".---": "J", "-.-": "K", ".-..": "L", "--": "M", "-.": "N", "---": "O", ".--.": "P",
         "--.-": "Q", ".-.": "R", "...": "S", "-": "T", "..-": "U", "...-": "V", ".--": "W", "-..-": "X",
         "-.--": "Y", "--..": "Z", "-----": "0", ".----": "1", "..---": "2", "...--": "3", "....-": "4",
         ".....": "5", "-....": "6", "--...": "7", "---..": "8", "----.": "9", ".-.-.": "+", "---...": ":"}


def decode(runs, unit=120):
    """ITU decode of alternating (on, ms) runs: on <= 2T dot else dash; off >= 2T ends a character
    (morse-led.md §7.1; the message has no word gaps)."""
    out, symbol = [], ""
    for on, ms in runs:
        if on:
            symbol += "." if ms <= 2 * unit else "-"
        elif ms >= 2 * unit and symbol:
            out.append(MORSE.get(symbol, "?"))
            symbol = ""
    if symbol:
        out.append(MORSE.get(symbol, "?"))
    return "".join(out)


def elements_runs(elements):
    return [(i % 2 == 0, ms) for i, ms in enumerate(elements)]


class Http:
    """One keep-alive connection (the sampling tests send thousands of requests)."""

    def __init__(self, port):
        self.c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)

    def json(self, method, path, body=None):
        data = None if body is None else json.dumps(body).encode()
        self.c.request(method, path, body=data, headers={"Content-Type": "application/json"} if data else {})
        r = self.c.getresponse()
        payload = r.read()
        return r.status, json.loads(payload) if payload else None

    def ok(self, method, path, body=None):
        status, doc = self.json(method, path, body)
        if not 200 <= status < 300:
            raise AssertionError(f"{method} {path}: {status} {doc}")
        return doc

    def close(self):
        self.c.close()



class WebSocketLive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu()
        cls.port = cls.m.ports["http"]

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def test_hello_then_status_at_20_hz_while_eight_refgo_clients_poll(self):
        stop = threading.Event()
        replies, bad = [0] * 8, []

        def poll(i):
            with socket.create_connection(("127.0.0.1", self.m.ports["refgo"]), timeout=5) as s:
                while not stop.is_set():
                    r = refgo_exchange(s, "TP")
                    if not re.fullmatch(rb"TP\r\n-?\d+\r\n>", r):
                        bad.append(r)
                    replies[i] += 1

        pollers = [threading.Thread(target=poll, args=(i,)) for i in range(8)]
        for t in pollers:
            t.start()
        ws = WebSocket(self.port)
        try:
            hello = ws.recv_json()
            self.assertEqual(hello["type"], "hello")
            self.assertEqual(hello["info"]["ports"]["refgo"], self.m.ports["refgo"])
            ws.send_json({"subscribe": ["status"]})
            first = ws.recv_type("status")
            seqs, times, start = [first["seq"]], [first["timeMs"]], time.monotonic()
            while time.monotonic() - start < 2.0:
                msg = ws.recv_type("status")
                seqs.append(msg["seq"])
                times.append(msg["timeMs"])
            self.assertIn("footer", first)
            self.assertEqual(first["refgo"]["clients"], 8)
        finally:
            ws.close()
            stop.set()
            for t in pollers:
                t.join()
        # web.md §10: 20 Hz; at least 10 Hz under this load (2 s hold >= 20 messages)
        self.assertGreaterEqual(len(seqs), 21, f"{len(seqs)} status messages in 2 s")
        self.assertEqual(seqs, sorted(seqs))
        self.assertEqual(times, sorted(times))
        self.assertEqual(bad, [])
        self.assertTrue(all(n > 0 for n in replies), replies)

    def test_trace_and_udp_subscriptions(self):
        ws = WebSocket(self.port)
        try:
            ws.recv_type("hello")
            ws.send_json({"subscribe": ["trace", "udp"]})
            time.sleep(0.1)  # the subscription is read before the request below is made
            h = Http(self.port)
            h.ok("GET", "/api/v1/info")
            h.close()
            msg = ws.recv_type("trace")
            lines = [e for e in msg["events"] if e.get("channel") == "http"]
            self.assertTrue(any("GET /api/v1/info" in json.dumps(e) for e in lines), msg)
            # a UDP console message: an emulator note of a RefGo connection (udp-debug.md §4.7),
            # on once the runtime setting is (web.md §8.9)
            h = Http(self.port)
            h.ok("PUT", "/api/v1/settings", {"udpEmulatorNotes": True})
            h.close()
            with socket.create_connection(("127.0.0.1", self.m.ports["refgo"]), timeout=5):
                udp = ws.recv_type("udp")
            self.assertIn("refgo client", json.dumps(udp))
        finally:
            ws.close()

    def test_cross_site_origin_is_403(self):
        with self.assertRaises(HandshakeRefused) as e:
            WebSocket(self.port, origin="http://attacker.example")
        self.assertIn(" 403 ", e.exception.status_line + " ")
        ws = WebSocket(self.port, origin=f"http://127.0.0.1:{self.port}")  # same origin: accepted
        self.assertEqual(ws.recv_json()["type"], "hello")
        ws.close()

    def test_seventeenth_client_is_503_and_a_slot_frees_on_close(self):
        clients = []
        try:
            for _ in range(16):
                clients.append(WebSocket(self.port))
                clients[-1].recv_type("hello")
            with self.assertRaises(HandshakeRefused) as e:
                WebSocket(self.port)
            self.assertIn(" 503 ", e.exception.status_line + " ")
            clients.pop().close()

            def accepted():
                try:
                    ws = WebSocket(self.port)
                except HandshakeRefused:
                    return False
                clients.append(ws)
                return True

            wait_for(accepted, what="a free WebSocket slot")
            self.assertEqual(clients[-1].recv_json()["type"], "hello")
        finally:
            for c in clients:
                c.close()


class WebSocketLimitFromConfig(unittest.TestCase):
    def test_http_ws_max_clients_sets_the_limit(self):
        with tempfile.TemporaryDirectory() as tmp:
            config = os.path.join(tmp, "ws.json")
            with open(config, "w") as f:
                json.dump({"http": {"ws_max_clients": 20}}, f)
            with Mcemu("--config", config) as m:
                clients = []
                try:
                    for _ in range(20):  # four more than the default of 16
                        clients.append(WebSocket(m.ports["http"]))
                        clients[-1].recv_type("hello")
                    with self.assertRaises(HandshakeRefused) as e:
                        WebSocket(m.ports["http"])
                    self.assertIn(" 503 ", e.exception.status_line + " ")
                finally:
                    for c in clients:
                        c.close()


class PowerCycle(unittest.TestCase):
    def test_stored_values_back_connections_closed_start_up_block_again(self):
        with Mcemu() as m:
            h = Http(m.ports["http"])
            h.ok("PUT", "/api/v1/objects/6081h/0", {"value": 12345})
            h.ok("POST", "/api/v1/store", {})
            h.ok("PUT", "/api/v1/objects/6081h/0", {"value": 999})  # not stored: lost by the power cycle
            refgo = socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5)
            refgo_exchange(refgo, "TP")
            udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            udp.bind(("127.0.0.1", 0))
            udp.settimeout(5)
            udp.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
            first_block = udp.recvfrom(4096)[0]
            self.assertTrue(first_block.startswith(b"SYS_Initialize"), first_block)

            self.assertEqual(h.ok("POST", "/api/v1/power-cycle", {})["ok"], True)

            self.assertEqual(h.ok("GET", "/api/v1/objects/6081h/0")["value"], 12345)
            refgo.settimeout(5)
            self.assertEqual(refgo.recv(4096), b"", "the RefGo connection is closed")
            refgo.close()
            # the listener was forgotten: it registers again and gets the start-up block again
            udp.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
            self.assertEqual(udp.recvfrom(4096)[0], first_block)
            # the drive serves new connections, and the status shows the start state again
            with socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5) as s:
                self.assertRegex(refgo_exchange(s, "TP"), rb"^TP\r\n-?\d+\r\n>$")
            self.assertEqual(h.ok("GET", "/api/v1/status")["footer"]["live"], "MC Live OFF")
            self.assertTrue(m.has_line("power cycle"))
            udp.close()
            h.close()


class Leds(unittest.TestCase):
    def test_schedule_decodes_to_the_factory_address(self):
        with Mcemu() as m:
            led = Http(m.ports["http"]).ok("GET", "/api/v1/led")["green"]
            self.assertEqual(led["text"], "MC+IP192+168+2+150:")
            self.assertEqual(decode(elements_runs(led["elements"])), led["text"])
            self.assertEqual(led["cycleMs"], 37200)
            self.assertEqual(sum(led["elements"]), 37200)
            self.assertEqual(sum(led["elements"][0::2]), 22080)

    def test_other_address(self):
        with Mcemu("--ip", "10.0.0.1") as m:
            led = Http(m.ports["http"]).ok("GET", "/api/v1/led")["green"]
            self.assertEqual(led["text"], "MC+IP10+0+0+1:")
            self.assertEqual(decode(elements_runs(led["elements"])), "MC+IP10+0+0+1:")
            self.assertEqual(led["cycleMs"], 234 * 120)

    def test_live_sampling_under_the_manual_clock(self):
        """morse-led.md §7.2 with 40 ms steps (every element is a multiple of 120 ms from t = 0)."""
        with Mcemu("--clock", "manual") as m:
            h = Http(m.ports["http"])
            cycle = h.ok("GET", "/api/v1/led")["green"]["cycleMs"]
            t0 = h.ok("GET", "/api/v1/status")["timeMs"]  # the boot-up steps ran (docs/decisions/0004)
            h.ok("POST", "/api/v1/clock/advance", {"ms": 120 - t0 % 120})  # the grid on a unit boundary
            self.assertEqual(h.ok("GET", "/api/v1/status")["timeMs"] % 120, 0)
            samples = []
            for _ in range(2 * cycle // 40):
                s = h.ok("GET", "/api/v1/status")
                samples.append(s["led"]["green"])
                h.ok("POST", "/api/v1/clock/advance", {"ms": 40})
            h.close()
        runs = []
        for on in samples:
            if runs and runs[-1][0] == on:
                runs[-1][1] += 40
            else:
                runs.append([on, 40])
        # the window starts at drive time t0, which may be inside a repetition: decode from the
        # first on-run that follows a gap of 3 units or more (a character boundary)
        self.assertTrue(all(ms in (120, 360) for _, ms in runs[1:-1]), runs)
        text = decode(runs)
        self.assertIn("MC+IP192+168+2+150:", text)
        self.assertGreaterEqual(text.count(":"), 1)

    def test_fault_text_from_the_next_repetition_and_back_after_reset(self):
        with Mcemu("--clock", "manual") as m:
            h = Http(m.ports["http"])
            h.ok("POST", "/api/v1/clock/advance", {"ms": 1000})
            fault = h.ok("POST", "/api/v1/faults", {"kind": "drive.inject", "cause": "stroke"})
            h.ok("POST", "/api/v1/clock/advance", {"ms": 10})
            led = h.ok("GET", "/api/v1/led")["green"]
            self.assertEqual(led["text"], "MC+IP192+168+2+150:")
            self.assertEqual(led["nextText"], "MC+IP192+168+2+150+ERR7121:")
            now = h.ok("GET", "/api/v1/status")["timeMs"]
            h.ok("POST", "/api/v1/clock/advance", {"ms": led["cycleStartMs"] + led["cycleMs"] - now + 1})
            led = h.ok("GET", "/api/v1/led")["green"]
            self.assertEqual(led["text"], "MC+IP192+168+2+150+ERR7121:")
            self.assertEqual(decode(elements_runs(led["elements"])), led["text"])
            # the cause removed and the fault reset (controlword bit 7): the normal text returns
            h.ok("DELETE", f"/api/v1/faults/{fault['id']}")
            h.ok("PUT", "/api/v1/objects/6040h/0", {"value": 0x80})
            h.ok("POST", "/api/v1/clock/advance", {"ms": 10})
            self.assertEqual(h.ok("GET", "/api/v1/status")["lastError"]["code"], 0x7121)
            led = h.ok("GET", "/api/v1/led")["green"]
            self.assertEqual(led["nextText"], "MC+IP192+168+2+150:")
            now = h.ok("GET", "/api/v1/status")["timeMs"]
            h.ok("POST", "/api/v1/clock/advance", {"ms": led["cycleStartMs"] + led["cycleMs"] - now + 1})
            self.assertEqual(h.ok("GET", "/api/v1/led")["green"]["text"], "MC+IP192+168+2+150:")
            h.close()

    def test_yellow_follows_refgo_connections_not_websockets(self):
        with Mcemu() as m:
            h = Http(m.ports["http"])
            self.assertFalse(h.ok("GET", "/api/v1/led")["yellow"]["on"])
            ws = WebSocket(m.ports["http"])
            ws.recv_type("hello")
            time.sleep(0.1)
            self.assertFalse(h.ok("GET", "/api/v1/led")["yellow"]["on"], "a WebSocket does not count")
            with socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5) as s:
                refgo_exchange(s, "TP")
                wait_for(lambda: h.ok("GET", "/api/v1/led")["yellow"]["connections"] == 1, what="one connection")
                for _ in range(30):
                    refgo_exchange(s, "TP")
                    time.sleep(0.01)
                yellow = h.ok("GET", "/api/v1/led")["yellow"]
                offs = [t for t, on in yellow["edges"] if not on]
                self.assertTrue(offs, "traffic flickers the LED")
                edges = yellow["edges"]
                for (t1, on1), (t2, on2) in zip(edges, edges[1:]):
                    if not on1 and on2:
                        self.assertEqual(t2 - t1, 40, edges)  # each flicker is 40 ms off
            wait_for(lambda: h.ok("GET", "/api/v1/led")["yellow"]["connections"] == 0, what="no connection")
            ws.close()
            h.close()


if __name__ == "__main__":
    unittest.main()
