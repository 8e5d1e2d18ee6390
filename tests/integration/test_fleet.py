"""Fleets in one process (issue 13, spec README --drives / --port-step / --fleet): every drive has
its own address (127.0.0.k), its own dictionary, core, CANopen node, web API, UDP console and state
file, and a client of one drive changes nothing on the others."""
import json
import os
import socket
import tempfile
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from slcan_client import Client


def refgo(address, port, line, timeout=5.0):
    """One RefGo command over TCP; returns the answer line (between echo and prompt) or None."""
    with socket.create_connection((address, port), timeout=timeout) as s:
        s.sendall(line.encode() + b"\r")
        data = b""
        deadline = time.monotonic() + timeout
        while not data.endswith(b">") and time.monotonic() < deadline:
            chunk = s.recv(4096)
            if not chunk:
                break
            data += chunk
    lines = data.decode().split("\r\n")
    assert lines[-1] == ">", data
    assert lines[0] == line, data  # the echo
    return lines[1] if len(lines) == 3 else None


def sdo_u32(address, port, index, sub):
    c = Client(port, address=address)
    try:
        c.nmt(0x80)  # pre-operational: SDO works without a boot-up on connect
        return int.from_bytes(c.upload(index, sub), "little")
    finally:
        c.close()


class DrivesFlag(unittest.TestCase):
    def test_three_drives_are_independent(self):
        with Mcemu("--drives", "3") as m:
            wait_for(lambda: len(m.drives) == 3 and all(len(d) == 4 for d in m.drives.values()), what="12 listeners")
            for k in (1, 2, 3):
                self.assertEqual(m.drives[k]["refgo"][0], f"127.0.0.{k}")
                self.assertEqual(m.count_lines(f"drive {k}: listening:"), 4)
            # Own reported address (5007h) per drive: --ip + (k-1).
            for k in (1, 2, 3):
                status, body = m.http("GET", "/api/v1/info", drive=k)
                self.assertEqual(status, 200)
                self.assertEqual(json.loads(body)["ip"], f"192.168.2.{149 + k}")
            # Each drive written through a different door: RefGo on 1, SDO on 2, HTTP on 3.
            address, port = m.drives[1]["refgo"]
            self.assertEqual(refgo(address, port, "OW6081,0,1111"), "OW6081,0,1111,OK")
            c = Client(m.drives[2]["slcan"][1], address=m.drives[2]["slcan"][0])
            try:
                c.nmt(0x80)
                c.download(0x6081, 0, (2222).to_bytes(4, "little"))
            finally:
                c.close()
            status, _ = m.http("PUT", "/api/v1/objects/6081/0", {"value": 3333}, drive=3)
            self.assertEqual(status, 200)
            # … and read back through the other doors.
            for k, expected in ((1, 1111), (2, 2222), (3, 3333)):
                address, port = m.drives[k]["refgo"]
                self.assertEqual(refgo(address, port, "OR6081,0"), f"OR6081,0,{expected}")
                self.assertEqual(sdo_u32(*m.drives[k]["slcan"], 0x6081, 0), expected)
                self.assertEqual(m.read_object_of(k, 0x6081, 0), expected)
            # A move on drive 2 moves drive 2 only.
            address, port = m.drives[2]["refgo"]
            refgo(address, port, "PWC")
            refgo(address, port, "G5000")
            wait_for(lambda: m.read_object_of(2, 0x6064, 0) == 5000, timeout=20, what="drive 2 at 5000")
            for k in (1, 3):
                self.assertEqual(m.read_object_of(k, 0x6064, 0), 0)
                self.assertEqual(m.read_object_of(k, 0x6041, 0) & 0x6F, 0x40)  # still switch on disabled

    def test_quiet_drives_keep_the_fleet_time_while_another_moves(self):
        """A fleet does not visit its quiet drives while another one steps (issue 26, sim::Fleet):
        they are brought up to date when a client reads them, and after every manual advance."""
        def time_of(m, k):
            return json.loads(m.http("GET", "/api/v1/clock", drive=k)[1])["timeMs"]

        def back_and_forth(m, k):
            address, port = m.drives[k]["refgo"]
            for line in ("PWC", "SP 5000", "RR 20000"):
                refgo(address, port, line)

        with Mcemu("--drives", "3", "--clock", "manual") as m:
            wait_for(lambda: len(m.drives) == 3, what="three drives")
            back_and_forth(m, 2)
            status, body = m.http("POST", "/api/v1/clock/advance", {"ms": 5000}, drive=2)
            self.assertEqual(status, 200)
            t = json.loads(body)["timeMs"]
            self.assertNotEqual(m.read_object_of(2, 0x6064, 0), 0, "drive 2 moved")
            status, body = m.http("POST", "/api/v1/clock/advance", {"ms": 3000}, drive=1)
            self.assertEqual(json.loads(body)["timeMs"], t + 3000, "the quiet drive's own answer")
            self.assertEqual([time_of(m, k) for k in (1, 2, 3)], [t + 3000] * 3)
        with Mcemu("--drives", "3") as m:
            wait_for(lambda: len(m.drives) == 3, what="three drives")
            back_and_forth(m, 3)
            time.sleep(0.5)
            t1, t3, t2 = time_of(m, 1), time_of(m, 3), time_of(m, 2)
            self.assertGreater(t1, 400)
            self.assertTrue(t1 <= t3 <= t2 < t1 + 1000, (t1, t3, t2))

    def test_store_and_restart_per_drive(self):
        with tempfile.TemporaryDirectory(prefix="mcemu-fleet-") as tmp:
            state = os.path.join(tmp, "state")
            with Mcemu("--drives", "2", state_dir=state) as m:
                wait_for(lambda: len(m.drives) == 2, what="two drives")
                status, _ = m.http("PUT", "/api/v1/objects/6083/0", {"value": 4321}, drive=2)
                self.assertEqual(status, 200)
                status, _ = m.http("POST", "/api/v1/store", {}, drive=2)
                self.assertEqual(status, 200)
                self.assertEqual(m.terminate(), 0)
            self.assertTrue(os.path.exists(os.path.join(state, "drive-2.json")))
            self.assertFalse(os.path.exists(os.path.join(state, "drive-1.json")))
            with Mcemu("--drives", "2", state_dir=state) as m:
                wait_for(lambda: len(m.drives) == 2, what="two drives")
                self.assertEqual(m.read_object_of(2, 0x6083, 0), 4321)
                self.assertNotEqual(m.read_object_of(1, 0x6083, 0), 4321)
                # The stored file keeps drive 2's own factory address.
                self.assertEqual(m.read_object_of(2, 0x5007, 4), 151)

    def test_port_step(self):
        with Mcemu("--drives", "2", "--port-step", "10", ports_zero=False, env={},
                   *self._free_base_ports()) as m:
            wait_for(lambda: len(m.drives) == 2, what="two drives")
            self.assertEqual(m.drives[1]["refgo"][0], "127.0.0.1")
            self.assertEqual(m.drives[2]["refgo"][0], "127.0.0.1")
            for service in ("refgo", "slcan", "http", "udp"):
                self.assertEqual(m.drives[2][service][1], m.drives[1][service][1] + 10)
            status, body = m.http("GET", "/api/v1/info", drive=2)
            self.assertEqual(json.loads(body)["ip"], "192.168.2.151")

    @staticmethod
    def _free_base_ports():
        """Four base ports p such that p and p + 10 are free for TCP and UDP right now."""
        chosen = []
        for _ in range(200):
            with socket.socket() as s:
                s.bind(("127.0.0.1", 0))
                p = s.getsockname()[1]
            if p + 10 > 65535 or p in chosen or p + 10 in chosen:
                continue
            ok = True
            for candidate in (p, p + 10):
                for kind in (socket.SOCK_STREAM, socket.SOCK_DGRAM):
                    with socket.socket(socket.AF_INET, kind) as t:
                        try:
                            t.bind(("127.0.0.1", candidate))
                        except OSError:
                            ok = False
            if ok:
                chosen.append(p)
            if len(chosen) == 4:
                break
        return ["--refgo-port", str(chosen[0]), "--slcan-port", str(chosen[1]), "--http-port", str(chosen[2]),
                "--udp-port", str(chosen[3])]


class ScriptEngineProbe(unittest.TestCase):
    def test_one_probe_for_the_whole_fleet(self):
        """The script engine's availability probe (python3, and bwrap for the sandbox) runs once per
        process, about 1 s after start, however many drives there are: a probe per drive cost a
        1000-drive fleet 1000 python3 starts."""
        with Mcemu("--drives", "20") as m:
            most = 0
            deadline = time.monotonic() + 4.0
            while time.monotonic() < deadline:
                with open(f"/proc/{m.proc.pid}/task/{m.proc.pid}/children") as f:
                    most = max(most, len(f.read().split()))
                time.sleep(0.02)
            self.assertLessEqual(most, 2, "python3 and bwrap once, not once per drive")
            wait_for(lambda: m.has_line("script engine"), what="the script engine's verdict")
            self.assertEqual(m.count_lines("script engine"), 1, "one verdict logged")


class FleetFile(unittest.TestCase):
    def test_mixed_models(self):
        with tempfile.TemporaryDirectory(prefix="mcemu-fleet-") as tmp:
            fleet = os.path.join(tmp, "fleet.json")
            with open(fleet, "w") as f:
                json.dump([{"model": "MC349", "ip": "10.0.0.10"},
                           {"model": "MCFLAT", "objects": {"6083.00": 2000}},
                           {"model": "MCFLAT", "bind": "127.0.0.9"}], f)
            with Mcemu("--fleet", fleet) as m:
                wait_for(lambda: len(m.drives) == 3, what="three drives")
                self.assertEqual(m.drives[3]["http"][0], "127.0.0.9")
                models = [json.loads(m.http("GET", "/api/v1/info", drive=k)[1])["model"] for k in (1, 2, 3)]
                self.assertEqual(models, ["MC349", "MCFLAT", "MCFLAT"])
                self.assertEqual(json.loads(m.http("GET", "/api/v1/info", drive=1)[1])["ip"], "10.0.0.10")
                self.assertEqual(m.read_object_of(2, 0x6083, 0), 2000)
                self.assertNotEqual(m.read_object_of(3, 0x6083, 0), 2000)
                self.assertNotEqual(m.read_object_of(1, 0x1008, 0), m.read_object_of(2, 0x1008, 0))

    def test_trace_ring_size_per_drive(self):
        # docs/fleet.md: "trace": {"events": N} in a fleet entry sizes that drive's trace ring only
        with tempfile.TemporaryDirectory(prefix="mcemu-fleet-") as tmp:
            fleet = os.path.join(tmp, "fleet.json")
            with open(fleet, "w") as f:
                json.dump([{"model": "MC349", "trace": {"events": 5}}, {"model": "MC349"}], f)
            with Mcemu("--fleet", fleet) as m:
                wait_for(lambda: len(m.drives) == 2, what="two drives")
                for k in (1, 2):
                    address, port = m.drives[k]["refgo"]
                    for i in range(10):
                        self.assertEqual(refgo(address, port, f"OW6081,0,{1000 + i}"), f"OW6081,0,{1000 + i},OK")
                small = json.loads(m.http("GET", "/api/v1/trace?limit=500", drive=1)[1])
                large = json.loads(m.http("GET", "/api/v1/trace?limit=500", drive=2)[1])
                self.assertEqual(len(small["events"]), 5)
                self.assertGreater(small["dropped"], 0)
                self.assertGreaterEqual(len(large["events"]), 20)  # each command: in and out
                self.assertEqual(large["dropped"], 0)
                self.assertEqual(small["events"][-1]["seq"], small["nextSeq"] - 1, "the newest stay")
            fleet_bad = os.path.join(tmp, "bad.json")
            with open(fleet_bad, "w") as f:
                json.dump([{"model": "MC349", "trace": {"events": 0}}], f)
            m = Mcemu("--fleet", fleet_bad, ready=False)
            self.assertEqual(m.wait_exit(), 2)
            self.assertIn('"trace.events" must be an integer 1 … 1000000', m.log())
            m.tmp.cleanup()

    def test_bad_fleet_file_is_a_usage_error(self):
        with tempfile.TemporaryDirectory(prefix="mcemu-fleet-") as tmp:
            fleet = os.path.join(tmp, "fleet.json")
            with open(fleet, "w") as f:
                json.dump([{"model": "MC349"}, {"model": "NOPE"}], f)
            m = Mcemu("--fleet", fleet, ready=False)
            self.assertEqual(m.wait_exit(), 2)
            self.assertIn("fleet entry 2: unknown model 'NOPE'", m.log())
            m.tmp.cleanup()


if __name__ == "__main__":
    unittest.main()
