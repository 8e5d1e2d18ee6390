"""Scripts under --clock manual (scripting.md §8.2, web.md §8.10): POST /api/v1/clock/advance keeps
in lock-step with the running script, so the same script gives the same output, line for line and
number for number, every time — and a sleep_ms(1000) loop prints once per 1000 ms advanced.
"""
import json
import re
import unittest

from mcemu_harness import Mcemu, wait_for
from script_client import RefGo, UdpConsole

SCRIPT = b"""#id lock-step
import time
import mcdrive as mc
t0 = time.ticks_ms()
mc.SetPosVel(100)
mc.GoPosAbs(300000)
for i in range(4):
    time.sleep_ms(1000)
    print(i, time.ticks_diff(time.ticks_ms(), t0), mc.GetActualPos(), mc.ChkReady())
n = 0
while time.ticks_diff(time.ticks_ms(), t0) < 4250:
    n += 1
    time.sleep_us(100)
print("end", time.ticks_diff(time.ticks_ms(), t0), n)
"""

LINE = re.compile(rb"(?:[0-9]+|end) [-0-9 ]+\r\n")


def advance(m, ms):
    status, body = m.http("POST", "/api/v1/clock/advance", {"ms": ms}, timeout=60)
    assert status == 200, (status, body)
    return json.loads(body)["timeMs"]


def printed(udp):
    return LINE.findall(udp.text())


class LockStep(unittest.TestCase):
    def run_once(self):
        """Starts SCRIPT on a fresh emulator and advances in uneven slices; the lines it printed
        and the drive time (since the start request) of the advance that printed each."""
        with Mcemu("--clock", "manual") as m:
            udp = UdpConsole(m.ports["udp"])
            status, _ = m.http("PUT", "/api/v1/script", SCRIPT, content_type="text/x-python")
            self.assertEqual(status, 200)
            t_start = json.loads(m.http("GET", "/api/v1/clock")[1])["timeMs"]  # the boot-up's few steps
            status, _ = m.http("POST", "/api/v1/script/start", {})
            self.assertEqual(status, 200)
            t = advance(m, 100)  # udp-debug.md §4.3: compile after 100 ms of drive time
            udp.wait_for(b"code: execute, script id: lock-step\n\r")
            seen = []
            for ms in [999, 1] + [250, 499, 251] * 3 + [300]:
                t = advance(m, ms)
                udp.poll(0.05)
                for line in printed(udp)[len(seen):]:
                    seen.append((t - t_start, line))
            wait_for(lambda: json.loads(m.http("GET", "/api/v1/script")[1])["state"] == "OFF", what="the end")
            rg = RefGo(m.ports["refgo"])
            tp = rg.tp()
            rg.close()
            udp.close()
            return seen, tp

    def test_same_script_same_result_twice(self):
        first, tp1 = self.run_once()
        second, tp2 = self.run_once()
        self.assertEqual(first, second, "reproducible under the manual clock")
        self.assertEqual(tp1, tp2)
        lines = [l for _, l in first]
        self.assertEqual(len(lines), 5, lines)
        # each sleep_ms(1000) returns exactly when its 1000 ms have been advanced
        for i, (t, line) in enumerate(first[:4]):
            fields = line.split()
            self.assertEqual(int(fields[0]), i)
            self.assertEqual(int(fields[1]), 1000 * (i + 1), line)
        self.assertEqual(first[0][0], 1100, "printed by the advance that reached t0 + 1000, not before")
        self.assertTrue(lines[-1].startswith(b"end 4250 "), lines[-1])
        self.assertEqual(int(lines[3].split()[3]), 1, "the move has ended by then (target reached)")
        self.assertEqual(int(lines[3].split()[2]), 300000)
        self.assertLess(int(lines[0].split()[2]), 300000, "still moving after 1 s at 100 rpm")


if __name__ == "__main__":
    unittest.main()
