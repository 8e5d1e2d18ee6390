"""The frame sequence of python-canopen's BaseNode402 (slcan-canopen.md §13, PYCO), replayed with
python-can over `socket://` against the real binary: python-canopen itself is not a Debian
package, so this test sends what it sends, in its order, and applies its own timeouts (0.4 s per
state transition, 0.8 s overall, 0.5 s for 6061h) to what comes back — on TPDOs only, as its
statusword/mode caches are fed by TPDOs."""
import struct
import unittest

from mcemu_harness import Mcemu
from slcan_client import Client, SdoAbort

NODE = 50
RPDO1, RPDO2, RPDO3 = 0x200 + NODE, 0x300 + NODE, 0x400 + NODE
TPDO1, TPDO2 = 0x180 + NODE, 0x280 + NODE
NO_SUB = 0x06090011

# BaseNode402's State402: (mask, value) of the statusword, controlwords of the transitions.
STATES = {"NOT READY TO SWITCH ON": (0x4F, 0x00), "SWITCH ON DISABLED": (0x4F, 0x40),
          "READY TO SWITCH ON": (0x6F, 0x21), "SWITCHED ON": (0x6F, 0x23),
          "OPERATION ENABLED": (0x6F, 0x27), "FAULT": (0x4F, 0x08), "FAULT REACTION ACTIVE": (0x4F, 0x0F),
          "QUICK STOP ACTIVE": (0x6F, 0x07)}
NEXT = {"SWITCH ON DISABLED": ("READY TO SWITCH ON", 0x06), "READY TO SWITCH ON": ("SWITCHED ON", 0x07),
        "SWITCHED ON": ("OPERATION ENABLED", 0x0F)}
HOMING = {"IN PROGRESS": 0x0000, "INTERRUPTED": 0x0400, "ATTAINED": 0x1000, "TARGET REACHED": 0x1400,
          "ERROR VELOCITY IS NOT ZERO": 0x2000, "ERROR VELOCITY IS ZERO": 0x2400}


def state_of(sw):
    for name, (mask, value) in STATES.items():
        if sw & mask == value:
            return name
    return None


class BaseNode402(unittest.TestCase):
    def setUp(self):
        self.m = Mcemu()
        self.c = Client(self.m.ports["slcan"])
        self.statusword = 0  # python-canopen's TPDO cache starts at 0
        self.mode_display = None
        self.rpdo2_cw = 0  # RPDO2's 6040h bytes: whatever its buffer holds

    def tearDown(self):
        self.c.close()
        self.m.__exit__(None, None, None)

    def feed(self, frame):
        if frame.arbitration_id == TPDO1:
            self.statusword = struct.unpack_from("<H", bytes(frame.data))[0]
        elif frame.arbitration_id == TPDO2:
            self.statusword = struct.unpack_from("<H", bytes(frame.data))[0]
            self.mode_display = struct.unpack_from("<b", bytes(frame.data), 2)[0]

    def wait(self, predicate, timeout):
        """Feeds TPDOs into the caches until predicate() holds or the client's timeout passes."""
        if predicate():
            return True
        return self.c.recv_until(lambda f: (self.feed(f), predicate())[1], timeout=timeout) is not None

    def read_pdo_configuration(self):
        """PdoBase.read(): communication record and mapping of RPDO1–4 and TPDO1–4, by SDO."""
        maps = {}
        for com, mapping in [(0x1400 + i, 0x1600 + i) for i in range(4)] + [(0x1800 + i, 0x1A00 + i) for i in range(4)]:
            self.c.upload(com, 1)
            trans_type = self.c.upload(com, 2)[0]
            if trans_type >= 254:
                for sub in (3, 5):  # tolerated when absent
                    try:
                        self.c.upload(com, sub)
                    except SdoAbort as e:
                        self.assertEqual(e.code, NO_SUB)
            try:
                self.c.upload(com, 6)
            except SdoAbort as e:
                self.assertEqual(e.code, NO_SUB)
            n = self.c.upload(mapping, 0)[0]
            maps[com] = [struct.unpack("<I", self.c.upload(mapping, s))[0] >> 16 for s in range(1, n + 1)]
        return maps

    def set_state(self, target):
        """BaseNode402.state setter: one transition at a time by RPDO1, each confirmed by TPDO."""
        deadline_steps = 0
        while state_of(self.statusword) != target:
            current = state_of(self.statusword)
            self.assertIn(current, NEXT, f"no path from {current} (statusword {self.statusword:#06x})")
            nxt, cw = NEXT[current]
            self.c.send(RPDO1, struct.pack("<H", cw))
            self.assertTrue(self.wait(lambda n=nxt: state_of(self.statusword) == n, 0.4), f"{current} → {nxt}")
            deadline_steps += 1
            self.assertLessEqual(deadline_steps, 3)

    def set_op_mode(self, mode):
        """BaseNode402.op_mode setter: 6502h check by SDO, RPDO2 (6040h bytes from its buffer), 6061h by TPDO."""
        supported = struct.unpack("<I", self.c.upload(0x6502, 0))[0]
        self.assertTrue(supported & (1 << (mode - 1)), f"mode {mode} in 6502h {supported:#x}")
        self.c.send(RPDO2, struct.pack("<Hb", self.rpdo2_cw, mode))
        self.assertTrue(self.wait(lambda: self.mode_display == mode, 0.5), f"6061h = {mode} on TPDO2")

    def test_setup_enable_move_and_home(self):
        self.c.nmt(0x80)  # node.nmt.state = 'PRE-OPERATIONAL'
        maps = self.read_pdo_configuration()  # setup_402_state_machine()
        self.assertEqual(maps[0x1400], [0x6040], "controlword through RPDO1")
        self.assertIn(0x6060, maps[0x1401], "mode through RPDO2")
        self.assertEqual(maps[0x1800], [0x6041], "statusword on TPDO1")
        self.assertIn(0x6061, maps[0x1801])
        self.c.nmt(0x01)  # node.nmt.state = 'OPERATIONAL': TPDO1/TPDO2 once, filling the caches
        self.assertTrue(self.wait(lambda: self.mode_display is not None and self.statusword != 0, 0.5))
        self.assertEqual(state_of(self.statusword), "SWITCH ON DISABLED")

        # node.op_mode = 'PROFILED POSITION'; node.state = 'OPERATION ENABLED'
        self.set_op_mode(1)
        self.set_state("OPERATION ENABLED")

        # a move: 607Ah by SDO, new set-point by RPDO1, acknowledge and target reached by TPDO1
        self.c.download(0x607A, 0, struct.pack("<i", 20000))
        self.c.send(RPDO1, struct.pack("<H", 0x1F))
        self.assertTrue(self.wait(lambda: self.statusword & 0x1000, 0.4), "set-point acknowledge")
        self.c.send(RPDO1, struct.pack("<H", 0x0F))
        self.assertTrue(self.wait(lambda: self.statusword & 0x0400 and not self.statusword & 0x1000, 10.0),
                        "target reached")
        self.assertEqual(struct.unpack("<i", self.c.upload(0x6064, 0))[0], 20000)

        # node.homing(): state OE, op_mode HOMING (RPDO2 carries controlword 0 → Switch on disabled,
        # as on a real drive), state OE again, then start; the polls must never see INTERRUPTED or
        # an error after the start.
        self.c.download(0x6098, 0, b"\x23")  # method 35, set by SDO
        self.c.download(0x607C, 0, struct.pack("<i", 0))
        self.set_op_mode(6)
        self.assertTrue(self.wait(lambda: state_of(self.statusword) == "SWITCH ON DISABLED", 0.4),
                        "the RPDO2 controlword 0 disabled the voltage")
        self.set_state("OPERATION ENABLED")
        self.c.send(RPDO1, struct.pack("<H", 0x0F))
        self.c.send(RPDO1, struct.pack("<H", 0x1F))
        self.assertTrue(self.wait(lambda: self.statusword & 0x3400 == HOMING["IN PROGRESS"], 0.4),
                        "the first TPDO after the start shows 'in progress'")
        seen = []
        self.assertTrue(self.wait(lambda: (seen.append(self.statusword & 0x3400),
                                           self.statusword & 0x3400 in (HOMING["ATTAINED"],
                                                                        HOMING["TARGET REACHED"]))[1], 2.0))
        self.assertNotIn(HOMING["INTERRUPTED"], seen)
        self.assertNotIn(HOMING["ERROR VELOCITY IS ZERO"], seen)
        self.assertEqual(struct.unpack("<i", self.c.upload(0x6064, 0))[0], 0, "home set here")


if __name__ == "__main__":
    unittest.main()
