"""The trace ring carries real traffic of every channel (web.md §8.6, refgo.md §13,
slcan-canopen.md §11.2, udp-debug.md §6): RefGo lines and replies per connection, SLCAN lines per
session, UDP datagrams both ways, drive core events, connect/disconnect — and the exports are
readable by the tools people use (python-can's can.LogReader for the candump log)."""
import json
import os
import socket
import tempfile
import unittest

import can

from mcemu_harness import Mcemu, wait_for
from nc_client import Nc
from slcan_client import Client


def events(m, channels, since=0):
    return json.loads(m.http("GET", f"/api/v1/trace?channels={channels}&since={since}&limit=10000")[1])["events"]


class RefgoTrace(unittest.TestCase):
    def test_lines_replies_overlong_and_connection_events(self):
        with Mcemu() as m:
            with Nc(m.ports["refgo"]) as nc:
                reply = nc.request("TP")
                nc.send(b"A" * 300 + b"\r")
                self.assertEqual(nc.replies(1)[0], b">")
                ev = wait_for(lambda: [e for e in events(m, "refgo") if e["dir"] == "tx"][1:] and events(m, "refgo"))
            conns = {e["conn"] for e in ev}
            self.assertEqual(len(conns), 1, ev)
            peer = ev[0]["peer"]
            self.assertRegex(peer, r"^127\.0\.0\.1:\d+$")
            self.assertTrue(all(e["peer"] == peer and e["channel"] == "refgo" for e in ev))
            seq = [(e["dir"], e["text"]) for e in ev]
            self.assertEqual(seq[0], ("event", "connect"))
            self.assertIn(("rx", "TP\r"), seq)
            self.assertIn(("tx", reply.decode()), seq)
            self.assertLess(seq.index(("rx", "TP\r")), seq.index(("tx", reply.decode())))
            overlong = [e for e in ev if e.get("overlong")]
            self.assertEqual(len(overlong), 1)
            self.assertEqual(overlong[0]["text"], "A" * 64)
            self.assertEqual(overlong[0]["dir"], "rx")
            wait_for(lambda: ("event", "disconnect") in [(e["dir"], e["text"]) for e in events(m, "refgo")],
                     what="disconnect event")
            status, text = m.http("GET", "/api/v1/trace/text?channels=refgo")
            self.assertEqual(status, 200)
            self.assertRegex(text.decode(), r"refgo rx #\d+ TP<CR>")
            self.assertIn("[overlong]", text.decode())


class SlcanTrace(unittest.TestCase):
    def test_sdo_upload_in_the_trace_and_the_candump_export(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                value = c.upload(0x6041, 0)
            finally:
                c.close()
            ev = events(m, "slcan")
            rx = [e for e in ev if e["dir"] == "rx"]
            tx = [e for e in ev if e["dir"] == "tx"]
            self.assertIn("t63284041600000000000\r", [e["text"] for e in rx])
            response = "t5B284B416000" + value.hex().upper() + "0000\r"
            self.assertIn(response, [e["text"] for e in tx])
            self.assertEqual(ev[0]["text"], "connect")
            self.assertTrue(all(e["conn"] == ev[0]["conn"] and e["peer"] == ev[0]["peer"] for e in ev))
            status, log = m.http("GET", "/api/v1/trace/candump")
            self.assertEqual(status, 200)
            with tempfile.TemporaryDirectory(prefix="tr-candump-") as d:
                path = os.path.join(d, "trace.log")
                with open(path, "wb") as f:
                    f.write(log)
                frames = list(can.LogReader(path))
            ids = [(f.arbitration_id, bytes(f.data).hex()) for f in frames]
            self.assertIn((0x632, "4041600000000000"), ids)
            self.assertIn((0x5B2, "4b416000" + value.hex() + "0000"), ids)
            self.assertTrue(all(f.timestamp > 1.6e9 for f in frames), "wall-clock stamps")


class ConnectionIds(unittest.TestCase):
    def test_one_counter_per_drive_across_channels(self):
        """A drive's RefGo, SLCAN and HTTP listeners share one counter of connection ids, so a `conn`
        in the trace names one connection whatever its channel (web.md §8.6)."""
        with Mcemu() as m:
            with Nc(m.ports["refgo"]) as nc:
                nc.request("TP")
            c = Client(m.ports["slcan"])
            try:
                c.upload(0x6041, 0)
            finally:
                c.close()
            m.http("GET", "/api/v1/status")
            with Nc(m.ports["refgo"]) as nc:
                nc.request("TP")

            def connects():
                ev = events(m, "refgo,slcan,http")
                found = [(e["channel"], e["conn"]) for e in ev if e["dir"] == "event" and e["text"] == "connect"]
                return found if {ch for ch, _ in found} == {"refgo", "slcan", "http"} and \
                    sum(ch == "refgo" for ch, _ in found) == 2 else None

            found = wait_for(connects, what="connect events of every channel")
            conns = [conn for _, conn in found]
            self.assertEqual(len(conns), len(set(conns)), found)
            self.assertEqual(sorted(conns), list(range(1, len(conns) + 1)), "counted from 1 without gaps")


class HttpPolling(unittest.TestCase):
    def test_the_pages_polling_is_marked_and_can_be_left_out(self):
        """web.md §8.6: requests with the header X-Mcemu-Poll (the pages' timers) are marked
        "polling" on the http channel, and GET /api/v1/trace?excludePolling=1 leaves them out."""
        import urllib.request
        with Mcemu() as m:
            base = f"http://127.0.0.1:{m.ports['http']}"
            for _ in range(3):
                req = urllib.request.Request(base + "/api/v1/status", headers={"X-Mcemu-Poll": "1"})
                with urllib.request.urlopen(req, timeout=10) as r:
                    r.read()
            m.http("GET", "/api/v1/info")
            ev = wait_for(lambda: [e for e in events(m, "http") if e["text"] == "GET /api/v1/info"] and
                          events(m, "http"), what="the info request in the trace")
            polled = [e for e in ev if e.get("polling")]
            self.assertEqual([(e["dir"], e["text"]) for e in polled], [("rx", "GET /api/v1/status"), ("tx", "200")] * 3)
            self.assertFalse(any(e.get("polling") for e in ev if e["text"] == "GET /api/v1/info"))
            status, body = m.http("GET", "/api/v1/trace?channels=http&limit=10000&excludePolling=1")
            self.assertEqual(status, 200)
            kept = json.loads(body)["events"]
            self.assertFalse(any(e.get("polling") for e in kept))
            self.assertNotIn("GET /api/v1/status", [e["text"] for e in kept])
            self.assertIn("GET /api/v1/info", [e["text"] for e in kept])


class UdpAndDriveTrace(unittest.TestCase):
    def test_datagrams_both_ways_with_the_ignored_flag_and_registration_time(self):
        with Mcemu() as m:
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.bind(("127.0.0.1", 0))
            s.settimeout(5)
            try:
                s.sendto(b"hello", ("127.0.0.1", m.ports["udp"]))
                s.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
                first = s.recvfrom(4096)[0]
            finally:
                s.close()
            ev = wait_for(lambda: [e for e in events(m, "udp") if e["dir"] == "tx"] and events(m, "udp"))
            rx = [e for e in ev if e["dir"] == "rx"]
            self.assertEqual([(e["text"], e.get("ignored", False)) for e in rx], [("hello", True), ("\r", False)])
            tx = [e for e in ev if e["dir"] == "tx"]
            self.assertEqual(tx[0]["text"].encode(), first)
            self.assertEqual(tx[0]["peer"], rx[1]["peer"])
            udp = json.loads(m.http("GET", "/api/v1/udp")[1])
            self.assertEqual(len(udp["listeners"]), 1)
            self.assertGreater(udp["listeners"][0]["registeredMs"], 0)
            self.assertRegex(udp["listeners"][0]["registeredWall"], r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z$")
            self.assertGreaterEqual(udp["listeners"][0]["registeredMs"], rx[1]["timeMs"])
            self.assertIn("[ignored]", m.http("GET", "/api/v1/trace/text?channels=udp")[1].decode())

    def test_udp_datagram_flickers_link_act(self):  # morse-led.md §5.2
        with Mcemu() as m:
            before = json.loads(m.http("GET", "/api/v1/led")[1])["yellow"]["edges"]
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            try:
                s.sendto(b"ignored payload", ("127.0.0.1", m.ports["udp"]))
            finally:
                s.close()
            after = wait_for(lambda: json.loads(m.http("GET", "/api/v1/led")[1])["yellow"]["edges"] != before and
                             json.loads(m.http("GET", "/api/v1/led")[1])["yellow"]["edges"], what="yellow flicker")
            self.assertGreater(len(after), len(before))

    def test_drive_events_fault_and_emcy(self):
        with Mcemu() as m:
            status, body = m.http("POST", "/api/v1/faults", {"kind": "drive.inject", "cause": "under_voltage"})
            self.assertEqual(status, 201, body)
            texts = wait_for(lambda: [e["text"] for e in events(m, "drive") if "FaultRaised" in e["text"]] and
                             [e["text"] for e in events(m, "drive")], what="fault event")
            self.assertIn("FaultRaised under_voltage 3221h", texts)
            self.assertTrue(any(t.startswith("Emcy 3221h reg 05h") for t in texts), texts)
            self.assertTrue(any(t.startswith("StateChanged") for t in texts), texts)
            self.assertTrue(all(e["dir"] == "event" for e in events(m, "drive")))


if __name__ == "__main__":
    unittest.main()
