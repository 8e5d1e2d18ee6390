"""The master lint against the real binary (docs/lint.md, issue 27): a deliberately sloppy CANopen
master and a careful one, written the way python-canopen drives a node (its SDO client waits for
each response and sends an abort after its 0.3 s timeout; its NMT, RPDO and guarding frames), with
python-can's slcan interface over socket:// — python-canopen itself is not a Debian package, so
the frames it would send are sent here in its order (as test_client_sequences.py does). The sloppy
master gets exactly the expected findings, in order; the careful one none at all. A RefGo host
that pipelines its commands, and the --lint and --clock manual switches, complete the picture."""
import json
import os
import socket
import struct
import tempfile
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from slcan_client import Client, SdoAbort

NODE = 50
RPDO1 = 0x200 + NODE
GUARD = 0x700 + NODE
SAVE = 0x65766173


def u16(v):
    return struct.pack("<H", v)


def u32(v):
    return struct.pack("<I", v)


class Master:
    """A python-canopen-like master on one SLCAN connection."""

    def __init__(self, port):
        self.c = Client(port, node=NODE)

    def close(self):
        self.c.close()

    def read(self, index, sub=0):
        return self.c.upload(index, sub)

    def write(self, index, sub, data):
        self.c.download(index, sub, data)

    def statusword(self):
        return struct.unpack("<H", self.read(0x6041))[0]

    def wait_state(self, mask, value, timeout=5.0):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.statusword() & mask == value:
                return
        raise AssertionError(f"statusword never reached {value:#06x} (mask {mask:#06x}): {self.statusword():#06x}")

    def nmt(self, command):
        self.c.nmt(command)

    def rpdo1(self, controlword):
        self.c.send(RPDO1, u16(controlword))

    def guard(self):
        """One node-guarding RTR and its answer."""
        self.c.send(GUARD, rtr=True, dlc=1)
        assert self.c.recv_until(lambda m: m.arbitration_id == GUARD and not m.is_remote_frame) is not None


def findings(m):
    status, body = m.http("GET", "/api/v1/lint")
    assert status == 200, body
    return json.loads(body)


class MasterLint(unittest.TestCase):
    def test_sloppy_canopen_master_gets_exactly_the_expected_findings(self):
        with Mcemu() as m:
            master = Master(m.ports["slcan"])
            try:
                # 1 stop the node, then an SDO read: no answer, python-canopen times out and aborts
                master.nmt(0x02)
                master.c.send(0x600 + NODE, struct.pack("<BHB", 0x40, 0x6041, 0) + bytes(4))
                self.assertEqual(master.c.collect(0.3, lambda f: f.arbitration_id == 0x580 + NODE), [])
                master.c.send(0x600 + NODE, struct.pack("<BHBI", 0x80, 0x6041, 0, 0x05040000))
                master.nmt(0x80)
                # 2 Enable operation straight from Switch on disabled: ignored
                master.write(0x6040, 0, u16(0x000F))
                self.assertEqual(master.statusword() & 0x4F, 0x40)
                # 3 a mapping entry written while RPDO1 is valid (refused in the fixed mapping)
                with self.assertRaises(SdoAbort):
                    master.write(0x1600, 1, u32(0x60400010))
                # 4 an RPDO in PRE-OPERATIONAL: ignored
                master.rpdo1(0x0006)
                # 5 Store, and at once (same write) the next request: the store's answer is pending
                # (one write to the slcan port, as a master that queues both frames at once sends them)
                store = struct.pack("<BHB", 0x23, 0x1010, 1) + u32(SAVE)
                read = struct.pack("<BHB", 0x40, 0x6041, 0) + bytes(4)
                master.c.bus._write(f"t{0x600 + NODE:03X}8{store.hex().upper()}\rt{0x600 + NODE:03X}8{read.hex().upper()}")
                master.c.collect(0.5, lambda f: f.arbitration_id == 0x580 + NODE)
                # 6 start and drive by RPDO without node guarding
                master.nmt(0x01)
                master.rpdo1(0x0006)
                master.wait_state(0x6F, 0x21)
                # 7 profile velocity enabled with a target already in 60FFh: the axis jumps
                master.write(0x6060, 0, bytes([3]))
                master.write(0x60FF, 0, u32(200))
                master.rpdo1(0x0007)
                master.rpdo1(0x000F)
                master.wait_state(0x6F, 0x27)
                wait_for(lambda: master.statusword() & 0x0100, timeout=5, what="the axis moving")
                # 8 profile position requested while it moves
                master.write(0x6060, 0, bytes([1]))
                master.rpdo1(0x0000)
            finally:
                master.close()
            got = findings(m)
            rules = [f["rule"] for f in got["recent"]]
            self.assertEqual(rules, ["canopen.sdo_while_stopped", "cia402.command_ignored",
                                     "canopen.pdo_mapping_while_valid", "canopen.rpdo_not_operational",
                                     "canopen.sdo_overlap", "canopen.motion_without_guarding",
                                     "cia402.enable_with_velocity_target", "cia402.mode_change_while_moving"],
                             json.dumps(got["recent"], indent=1, ensure_ascii=False))
            self.assertEqual(got["totals"]["suppressed"], 0)
            self.assertTrue(all(f["conn"] != 0 for f in got["recent"]), "every finding names its connection")
            # the trace channel lint has the same findings, one event each
            status, body = m.http("GET", "/api/v1/trace?channels=lint&limit=100")
            events = json.loads(body)["events"]
            self.assertEqual([e["text"].split(" ")[0] for e in events], rules)

    def test_careful_canopen_master_gets_no_finding(self):
        with tempfile.TemporaryDirectory() as tmp:
            config = os.path.join(tmp, "config.json")
            with open(config, "w") as f:
                json.dump({"canopen": {"dynamic_pdo_mapping": True}}, f)
            with Mcemu("--config", config) as m:
                master = Master(m.ports["slcan"])
                try:
                    master.nmt(0x80)
                    self.assertEqual(len(master.read(0x1000)), 4)  # device type
                    # RPDO1 remapped the CiA 301 way: invalid, sub 0 = 0, entries, sub 0 = n, valid
                    master.write(0x1400, 1, u32(0x80000000 | RPDO1))
                    master.write(0x1600, 0, bytes([0]))
                    master.write(0x1600, 1, u32(0x60400010))
                    master.write(0x1600, 0, bytes([1]))
                    master.write(0x1400, 1, u32(RPDO1))
                    # node guarding: 1 s × 3, and the master's guarding RTRs from now on
                    master.write(0x100C, 0, u16(1000))
                    master.write(0x100D, 0, bytes([3]))
                    master.guard()
                    master.nmt(0x01)
                    master.write(0x6060, 0, bytes([3]))
                    master.write(0x60FF, 0, u32(0))  # no target before the enable
                    for cw, state in ((0x06, 0x21), (0x07, 0x23), (0x0F, 0x27)):
                        master.guard()
                        master.rpdo1(cw)
                        master.wait_state(0x6F, state)
                    master.write(0x60FF, 0, u32(200))
                    wait_for(lambda: master.statusword() & 0x0100, timeout=5, what="the axis moving")
                    master.guard()
                    master.write(0x60FF, 0, u32(0))
                    deadline = time.monotonic() + 10
                    while master.statusword() & 0x0100 and time.monotonic() < deadline:
                        master.guard()
                    self.assertFalse(master.statusword() & 0x0100, "the axis stopped")
                    master.write(0x6060, 0, bytes([1]))  # at standstill
                    master.rpdo1(0x0006)
                    master.wait_state(0x6F, 0x21)
                    master.write(0x1010, 1, u32(SAVE))  # one store, at standstill
                    master.guard()
                    master.nmt(0x80)
                finally:
                    master.close()
                got = findings(m)
                self.assertEqual(got["recent"], [], json.dumps(got["recent"], indent=1, ensure_ascii=False))
                self.assertEqual(got["totals"], {"info": 0, "warn": 0, "error": 0, "suppressed": 0, "failing": 0})

    def test_refgo_host_that_pipelines_and_the_mode_switches(self):
        with Mcemu("--lint", "strict") as m:
            with socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5) as s:
                s.sendall(b"TP\rTS\r")
                got = b""
                while got.count(b">") < 2:
                    got += s.recv(4096)
            body = findings(m)
            self.assertEqual(body["mode"], "strict")
            self.assertEqual([f["rule"] for f in body["recent"]], ["refgo.request_before_reply"])
            self.assertEqual(body["totals"]["failing"], 1, "strict: a warn-level finding fails")
            status, info = m.http("GET", "/api/v1/info")
            self.assertEqual(json.loads(info)["lint"], {"mode": "strict", "timing": True})
        with Mcemu("--lint", "off") as m:
            with socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5) as s:
                s.sendall(b"TP\rTS\r")
                got = b""
                while got.count(b">") < 2:
                    got += s.recv(4096)
            self.assertEqual(findings(m)["recent"], [])
        with Mcemu("--clock", "manual") as m:
            self.assertEqual(json.loads(m.http("GET", "/api/v1/info")[1])["lint"], {"mode": "warn", "timing": False})


if __name__ == "__main__":
    unittest.main()
