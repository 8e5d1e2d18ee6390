"""Fault injection over the JSON API (web.md §9) seen by a CANopen client: an injected fault
produces its EMCY on 0x80 + node (slcan-canopen.md §7) and the fault reset produces EMCY 0000h."""
import json
import unittest

from mcemu_harness import Mcemu, wait_for
from slcan_client import Client

EMCY = 0x80 + 50


class InjectedFaults(unittest.TestCase):
    def test_injected_under_voltage_gives_emcy_3221_then_0000_after_reset(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                status, body = m.http("POST", "/api/v1/faults", {"kind": "drive.inject", "cause": "under_voltage"})
                self.assertEqual(status, 201, body)
                fid = json.loads(body)["id"]
                frame = c.recv_until(lambda f: f.arbitration_id == EMCY, timeout=5)
                self.assertIsNotNone(frame, "no EMCY frame")
                self.assertEqual(bytes(frame.data).hex(), "2132050000000000")  # slcan-canopen.md §7.4
                self.assertEqual(m.read_object(0x603F, 0), 0x3221)
                self.assertEqual(m.read_object(0x1001, 0), 0x05)
                self.assertEqual(m.read_object(0x1003, 1), 0x3221)
                # the cause is removed; a fault reset by controlword then succeeds and sends EMCY 0000h
                self.assertEqual(m.http("DELETE", f"/api/v1/faults/{fid}")[0], 200)
                self.assertEqual(m.write_object(0x6040, 0, 0x0080)[0], 200)
                frame = c.recv_until(lambda f: f.arbitration_id == EMCY, timeout=5)
                self.assertIsNotNone(frame, "no reset EMCY")
                self.assertEqual(bytes(frame.data).hex(), "0000000000000000")
                wait_for(lambda: m.read_object(0x6041, 0) & 0x004F == 0x0040, what="switch on disabled")
            finally:
                c.close()

    def test_emcy_by_code_and_listing(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                self.assertEqual(m.http("POST", "/api/v1/faults", {"kind": "drive.emcy", "code": "4210h"})[0], 201)
                frame = c.recv_until(lambda f: f.arbitration_id == EMCY, timeout=5)
                self.assertIsNotNone(frame)
                self.assertEqual(bytes(frame.data[:3]).hex(), "104209")
                status, body = m.http("POST", "/api/v1/faults", {"kind": "drive.load", "value": 0.01})
                self.assertEqual(status, 201)
                listed = json.loads(m.http("GET", "/api/v1/faults")[1])["faults"]
                self.assertEqual([f["kind"] for f in listed], ["drive.load"], "the one-shot EMCY removed itself")
                self.assertEqual(m.http("DELETE", "/api/v1/faults")[0], 200)
                self.assertEqual(json.loads(m.http("GET", "/api/v1/faults")[1])["faults"], [])
                self.assertEqual(m.http("POST", "/api/v1/faults", {"kind": "refgo.gremlins"})[0], 400)
                self.assertEqual(m.http("POST", "/api/v1/faults", {"kind": "drive.inject"}, "text/plain")[0], 415)
            finally:
                c.close()


if __name__ == "__main__":
    unittest.main()
