"""Clock modes against the real binary (docs/clock.md, issue 13): under --clock manual drive time
stands still until POST /api/v1/clock/advance, and a 10-minute machine cycle runs in one request
with everything timed following drive time (heartbeats, a timed jog, the LED schedule); under
--clock scaled:X the heartbeat period is the drive-time period. Assertions are on drive time, never
on wall time."""
import json
import socket
import struct
import time
import unittest

from mcemu_harness import Mcemu
from mcemu_harness import refgo_line as refgo
from slcan_client import Client as SlcanClient



def api(m, method, path, body=None):
    status, data = m.http(method, path, body, timeout=120)
    if status != 200:
        raise AssertionError(f"{method} {path}: {status} {data!r}")
    return json.loads(data)


def heartbeat(msg):
    return msg.arbitration_id == 0x732 and bytes(msg.data) == b"\x05"


class ManualClock(unittest.TestCase):
    def test_time_stands_still_then_a_ten_minute_cycle_in_one_request(self):
        with Mcemu("--clock", "manual") as m:
            self.assertEqual(api(m, "GET", "/api/v1/clock")["mode"], "manual")
            c = SlcanClient(m.ports["slcan"])
            try:
                c.download(0x1017, 0, struct.pack("<H", 1000))
                c.nmt(0x01)  # operational: heartbeat state 05h
                t0 = api(m, "GET", "/api/v1/status")["timeMs"]
                self.assertEqual(c.collect(0.3, heartbeat), [], "no heartbeat while drive time stands still")
                self.assertEqual(api(m, "GET", "/api/v1/status")["timeMs"], t0)
                with socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=10) as s:
                    refgo(s, "PWC")
                    refgo(s, "SP 2000")
                    refgo(s, "JP 300000")  # jog positive, stop after 300 s of drive time
                    done = api(m, "POST", "/api/v1/clock/advance", {"ms": 299_990})
                    self.assertEqual(done["timeMs"], t0 + 299_990)
                    self.assertEqual(api(m, "GET", "/api/v1/status")["footer"]["live"], "MC Live MOV")
                    api(m, "POST", "/api/v1/clock/advance", {"ms": 300_010})
                    status = api(m, "GET", "/api/v1/status")
                    self.assertEqual(status["timeMs"], t0 + 600_000)
                    self.assertEqual(status["footer"]["live"], "MC Live RDY", "the jog stopped at 300 s")
                    pos = int(refgo(s, "TP").split(b"\r\n")[1])
                    self.assertGreater(pos, 100_000)
                    # drive time stands still again: the position does not change
                    time.sleep(0.2)
                    self.assertEqual(int(refgo(s, "TP").split(b"\r\n")[1]), pos)
                beats = []
                while (msg := c.recv_until(heartbeat, timeout=2.0)) is not None:
                    beats.append(msg)
                self.assertIn(len(beats), (599, 600, 601), "one heartbeat per 1000 ms of drive time")
            finally:
                c.close()

    def test_advance_validation(self):
        with Mcemu("--clock", "manual") as m:
            for body in ({}, {"ms": -1}, {"ms": "10"}, {"ms": 1.5}):
                status, _ = m.http("POST", "/api/v1/clock/advance", body)
                self.assertEqual(status, 400, body)

    def test_advance_is_refused_under_the_real_clock(self):
        with Mcemu() as m:
            status, data = m.http("POST", "/api/v1/clock/advance", {"ms": 10})
            self.assertEqual(status, 409, data)


class ScaledClock(unittest.TestCase):
    def test_heartbeat_period_is_drive_time(self):
        with Mcemu("--clock", "scaled:10") as m:
            clock = api(m, "GET", "/api/v1/clock")
            self.assertEqual((clock["mode"], clock["scale"]), ("scaled", 10))
            c = SlcanClient(m.ports["slcan"])
            try:
                c.download(0x1017, 0, struct.pack("<H", 1000))
                c.nmt(0x01)
                c.recv_until(heartbeat, timeout=5)
                t1 = api(m, "GET", "/api/v1/status")["timeMs"]
                beats = 0
                while beats < 20:
                    self.assertIsNotNone(c.recv_until(heartbeat, timeout=5), "heartbeats keep coming")
                    beats += 1
                t2 = api(m, "GET", "/api/v1/status")["timeMs"]
            finally:
                c.close()
            # 20 periods of 1000 ms of drive time lie between the two readings (± one period for
            # the phase of the readings)
            self.assertGreaterEqual(t2 - t1, 19_000)
            self.assertLessEqual(t2 - t1, 22_000)


if __name__ == "__main__":
    unittest.main()
