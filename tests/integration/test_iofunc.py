"""A machine built only from MovingCap I/O functions (iofunc.md), run by the real mcemu binary and
driven through RefGo as a PLC would drive the 24 V wires: the inputs are simulated with
`OW3510,1,…` (virtual inputs, iofunc.md §2.1) and the drive is observed with `TI`, `TP`, `OR6041,0`
and `OR60FE,1`. Nothing but I/O functions moves the drive:

    IN1 → timed motion absolute to A     IN3 → quick stop
    IN2 → timed motion absolute to B     IN4 → software enable (high active)
    OUT1/OUT2 → "position reached and status OK", bit-coded (255): which target is held

Every wait polls with a bound; nothing sleeps a fixed time.
"""
import re
import time
import unittest

from mcemu_harness import Mcemu
from nc_client import Nc

A = 10000
B = 30000
IN = {n: 1 << (15 + n) for n in range(1, 11)}
OUT1 = 1 << 16
OUT2 = 1 << 17
VALUE = re.compile(rb",(-?[0-9]+)\r\n>\Z")


class Drive:
    """RefGo helpers over one nc connection."""

    def __init__(self, test, nc):
        self.t = test
        self.nc = nc
        self.virtual = 0

    def ow(self, index, sub, value):
        line = f"OW{index},{sub},{value}"
        self.t.assertEqual(self.nc.request(line), f"{line}\r\n{line},OK\r\n>".encode())

    def read(self, index, sub):
        r = self.nc.request(f"OR{index},{sub}")
        m = VALUE.search(r)
        self.t.assertIsNotNone(m, r)
        return int(m.group(1))

    def tp(self):
        r = self.nc.request("TP")
        m = re.search(rb"TP\r\n(-?[0-9]+)\r\n>\Z", r)
        self.t.assertIsNotNone(m, r)
        return int(m.group(1))

    def ti(self, n=None):
        line = "TI" if n is None else f"TI{n}"
        r = self.nc.request(line)
        m = re.search(rb"\r\n([0-9a-f]+)\r\n>\Z", r)
        self.t.assertIsNotNone(m, r)
        return m.group(1).decode()

    def inputs(self, bits, high):
        self.virtual = (self.virtual | bits) if high else (self.virtual & ~bits)
        self.ow("3510", 1, self.virtual)

    def pulse(self, n):
        self.inputs(IN[n], True)
        self.inputs(IN[n], False)

    def statusword(self):
        return self.read("6041", 0)

    def outputs(self):
        return self.read("60FE", 1)

    def until(self, predicate, what, timeout=20.0):
        deadline = time.monotonic() + timeout
        while True:
            value = predicate()
            if value:
                return value
            if time.monotonic() > deadline:
                self.t.fail(f"{what} not reached within {timeout} s")
            time.sleep(0.002)

    def held(self, target, outputs):
        """Target reached (6041h bit 10), position within the window, outputs as expected."""
        self.until(lambda: self.statusword() & 0x0400 and abs(self.tp() - target) <= 10 and
                   self.outputs() & (OUT1 | OUT2) == outputs, f"{target} held with outputs {outputs:#x}")


class IoMachine(unittest.TestCase):
    def configure(self, d):
        d.ow("6067", 0, 10)
        for index, target in (("3511", A), ("3512", B)):
            d.ow(index, 1, 0x0400)  # rising edge: function 4
            d.ow(index, 8, target)
            d.ow(index, 6, 1000)
        d.ow("3513", 1, 0x0500)  # quick stop
        d.ow("3514", 1, 0x0900)  # software enable, high active
        for index in ("3611", "3612"):
            d.ow(index, 1, 6)  # position reached and status OK
            d.ow(index, 2, 255)  # bit-coded over the inputs with function 4
            d.ow(index, 5, 20)
            d.ow(index, 6, 20)

    def test_machine_sequence_through_refgo(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            d = Drive(self, nc)
            self.configure(d)
            self.assertEqual(d.statusword() & 0x6F, 0x40)

            # IN1 without the software enable: the move's switch-on attempt faults with FFF2h
            d.pulse(1)
            d.until(lambda: d.statusword() & 0x0008, "fault FFF2h")
            self.assertEqual(d.read("603F", 0), 0xFFF2)
            self.assertEqual(d.read("3511", 4), 0)
            d.until(lambda: d.outputs() == 0, "outputs low on fault")

            # IN4 high: TI shows it, the inputs word 60FDh too
            d.inputs(IN[4], True)
            self.assertEqual(d.ti(), "0008")
            self.assertEqual(d.ti(4), "1")
            self.assertEqual(d.ti(1), "0")
            self.assertEqual(d.read("60FD", 0), IN[4])

            # IN1: fault reset, switch on, move to A; OUT1 = code 1
            d.pulse(1)
            d.held(A, OUT1)
            self.assertEqual(d.read("3511", 3), A)
            self.assertEqual(d.read("3511", 4), 1)
            self.assertEqual(d.statusword() & 0x6F, 0x27)

            # IN2: move to B; OUT2 = code 2
            d.pulse(2)
            d.held(B, OUT2)
            self.assertEqual(d.read("3512", 4), 1)

            # IN1 towards A, then IN3 (quick stop) while it is on its way
            d.pulse(1)
            d.until(lambda: d.tp() < B - 200, "moving towards A")
            d.pulse(3)
            d.until(lambda: d.statusword() & 0x6F == 0x07, "quick stop active")
            self.assertEqual(d.read("605A", 0), 6)
            d.until(lambda: d.read("606C", 0) == 0, "standstill")
            stop = d.tp()
            self.assertGreater(stop, A + 100)
            self.assertLess(stop, B - 100)
            d.until(lambda: d.outputs() & (OUT1 | OUT2) == 0, "no target held after the stop")

            # IN2: leaves Quick Stop Active on its own and returns to B
            d.pulse(2)
            d.held(B, OUT2)

            # IN4 low: the drive switches off without a fault; B is still held and OK
            d.inputs(IN[4], False)
            d.until(lambda: d.statusword() & 0x4F == 0x40, "switch on disabled")
            self.assertEqual(d.read("1002", 0) & 0x200, 0)
            d.until(lambda: d.outputs() & (OUT1 | OUT2) == OUT2, "B still held")

            # IN1 again without the enable: fault, the outputs drop
            d.pulse(1)
            d.until(lambda: d.statusword() & 0x0008, "fault FFF2h again")
            d.until(lambda: d.outputs() & (OUT1 | OUT2) == 0, "outputs low")
            self.assertEqual(d.read("3511", 4), 2)

    def test_outputs_owned_by_functions_ignore_so_co(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            d = Drive(self, nc)
            self.assertEqual(nc.request("SO1"), b"SO1\r\n>")
            self.assertEqual(d.outputs(), OUT1)
            d.ow("3612", 1, 5)  # OUT2 = drive OK
            d.until(lambda: d.outputs() == OUT1 | OUT2, "OUT2 high by its function")
            self.assertEqual(nc.request("CO2"), b"CO2\r\n>")
            self.assertEqual(nc.request("CO1"), b"CO1\r\n>")
            self.assertEqual(d.outputs(), OUT2)
            d.ow("3612", 1, 0)
            self.assertEqual(d.outputs(), 0)

    def test_input_function_command_3510_2(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            d = Drive(self, nc)
            d.ow("3513", 8, -2000)
            d.ow("3513", 6, 500)
            d.ow("3510", 2, 772)  # 0304h: function 4 with the record of IN3 (manual 7.1.13)
            d.until(lambda: d.read("3513", 4) == 1, "command executed")
            self.assertEqual(d.read("607A", 0), -2000)
            self.assertEqual(d.read("3513", 3), -2000)
            self.assertEqual(d.read("3510", 2), 772)
            self.assertEqual(nc.request("OW3510,2,777"), b"OW3510,2,777\r\nOW3510,2,777,ERROR,06090030h\r\n>")


if __name__ == "__main__":
    unittest.main()
