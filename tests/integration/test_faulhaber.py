"""The FAULHABER MotionController personality over its binary RS232 protocol (faulhaber.md §2–§6,
§11 items 5, 6 and 9; issue 24): the real binary, driven through the pseudo-terminal with pyserial
and over TCP with pyserial's socket:// transport, by the test client `faulhaber_client.py`.

Frames are compared byte for byte with the example table of faulhaber.md §5 where it has them.
"""
import json
import os
import socket
import tempfile
import time
import unittest

import faulhaber_client as fc
from mcemu_harness import Mcemu, wait_for

FH = ("--model", "FH_MC5005")

# faulhaber.md §5, example table (node 1)
READ_6041 = bytes.fromhex("53 07 01 01 41 60 00 73 45")
ANSWER_6041_0040 = bytes.fromhex("53 09 01 01 41 60 00 40 00 C2 45")
WRITE_6040_06 = bytes.fromhex("53 09 01 02 40 60 00 06 00 2C 45")
ANSWER_WRITE_6040 = bytes.fromhex("53 07 01 02 40 60 00 DB 45")
WRITE_6060_3 = bytes.fromhex("53 08 01 02 60 60 00 03 A2 45")
ANSWER_WRITE_6060 = bytes.fromhex("53 07 01 02 60 60 00 FB 45")
READ_1234 = bytes.fromhex("53 07 01 01 34 12 00 8B 45")
ERROR_1234 = bytes.fromhex("53 0B 01 03 34 12 00 00 00 02 06 2B 45")
WRITE_6041 = bytes.fromhex("53 09 01 02 41 60 00 00 00 2B 45")
ERROR_6041 = bytes.fromhex("53 0B 01 03 41 60 00 02 00 01 06 78 45")
READ_3005_09 = bytes.fromhex("53 07 01 01 05 30 09 3B 45")
BOOT_MC5005 = bytes.fromhex("53 0B 01 00 4D 43 20 35 30 30 35 8E 45")
RESET_NODE = bytes.fromhex("53 04 01 00 50 45")
CW_COMMAND_06 = bytes.fromhex("53 06 01 04 06 00 50 45")
CW_COMMAND_0F = bytes.fromhex("53 06 01 04 0F 00 59 45")
CW_ANSWER_OK = bytes.fromhex("53 05 01 04 00 55 45")
SW_0040 = bytes.fromhex("53 06 01 05 40 00 17 45")
SW_0021 = bytes.fromhex("53 06 01 05 21 00 23 45")
SW_0027 = bytes.fromhex("53 06 01 05 27 00 8F 45")
SW_0427 = bytes.fromhex("53 06 01 05 27 04 21 45")
EMCY_ERROR_RESET = bytes.fromhex("53 0C 01 07 00 00 00 00 00 00 00 00 A0 45")


def config_file(doc):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(doc, f)
    f.close()
    return f.name


def recv_exactly(sock, n, timeout=5.0):
    sock.settimeout(timeout)
    data = b""
    while len(data) < n:
        chunk = sock.recv(n - len(data))
        if not chunk:
            raise ConnectionError(f"closed after {data.hex(' ')}")
        data += chunk
    return data


def nothing_more(sock, wait=0.2):
    """True when nothing arrives within `wait` seconds (used only to prove an absence)."""
    sock.settimeout(wait)
    try:
        sock.recv(1)  # data, or b"" for a closed connection: either way not "nothing"
        return False
    except socket.timeout:
        return True


def pty_path(m):
    for line in m.log().splitlines():
        if "listening: faulhaber pty " in line:
            return line.split("listening: faulhaber pty ")[1].split(" -> ")[0]
    return None


def target_reached_via_http(m, target):
    status = m.read_object(0x6041, 0)
    return (status & 0x0400) and m.read_object(0x6064, 0) == target


class RealClientThroughThePty(unittest.TestCase):
    """§11 item 9 / issue 24 item 5: a client driven exactly as the public mc5005.py drives an MC 5005
    (flush input, send, the first frame that comes is the answer, value from byte 7), through the
    pseudo-terminal with pyserial: read 1018h.04 and 6041h, PP mode, enable with 0x06/0x07/0x0F, an
    absolute move (607Ah, then 0x0F and 0x3F as its positionAbsolute does), the position read back."""

    def session(self, async_messages):
        with tempfile.TemporaryDirectory() as tmp:
            link = os.path.join(tmp, "ttyFH")
            cfg = config_file({"faulhaber": {"serial": 202400191}})
            try:
                with Mcemu(*FH, "--faulhaber-pty", link, "--config", cfg) as m:
                    self.assertEqual(pty_path(m), link)
                    self.assertTrue(os.path.islink(link))
                    c = fc.open_pty(link)
                    try:
                        self.run_client(m, c, async_messages)
                    finally:
                        c.close()
                self.assertFalse(os.path.lexists(link), "the symlink is removed at exit")
            finally:
                os.unlink(cfg)

    def run_client(self, m, c, async_messages):
        if not async_messages:
            c.simple_write(0x2400, 0x04, 0, 4)  # no EMCY, no asynchronous messages (the RS232 note's advice)
            self.assertEqual(c.last_simple_answer, bytes.fromhex("53 07 01 02 00 24 04 8E 45"))
        self.assertEqual(c.simple_read(0x1018, 4), 202400191)  # Serial Number
        serial_answer = fc.frame(1, 1, bytes.fromhex("18 10 04") + (202400191).to_bytes(4, "little"))
        self.assertEqual(c.last_simple_answer, serial_answer)
        self.assertEqual(c.simple_read(0x6041, 0, signed=False), 0x0040)
        self.assertEqual(c.last_simple_answer, ANSWER_6041_0040)
        # setPositionMode: node + 02 + 60 60 00 + 01 (a 1-byte value)
        c.simple_request(fc.frame(1, 2, bytes.fromhex("60 60 00 01")))
        self.assertEqual(c.last_simple_answer, ANSWER_WRITE_6060)
        for cw in (0x06, 0x07, 0x0F):  # shutDown, switchOn, enable
            c.simple_write(0x6040, 0, cw, 2)
            self.assertEqual(c.last_simple_answer, ANSWER_WRITE_6040, "the response comes before its notifications")
        target = 0x4000 * 3  # three turns of a 16384-increment example (mc5005.py moves multiples of 0x4000)
        c.simple_write(0x607A, 0, target, 4)  # positionAbsolute: setTarget, 0x0F, 0x3F
        c.simple_write(0x6040, 0, 0x0F, 2)
        c.simple_write(0x6040, 0, 0x3F, 2)
        if async_messages:
            # Only after the move has ended (faulhaber.md §11 item 9): the observer is the JSON API,
            # so that nothing but the client's own requests travels on the pty.
            wait_for(lambda: target_reached_via_http(m, target), timeout=30, what="move finished")
            # the notifications of the move are on the line; the client flushes them before its request
            # (read here to prove they were sent; the client's next request would flush them anyway)
            frames = []
            while not frames or frames[-1].raw != SW_0427:
                f = c.read_frame(timeout=5)
                self.assertIsNotNone(f, f"no 0x0427 notification after {frames!r}")
                frames.append(f)
            self.assertTrue(all(f.command == fc.STATUSWORD for f in frames), frames)
        else:
            # TargetReached as mc5005.py does it: poll 6041h until bit 10
            deadline = time.monotonic() + 30
            while not c.simple_read(0x6041, 0, signed=False) & 0x0400:
                self.assertLess(time.monotonic(), deadline, "target never reached")
        self.assertEqual(c.simple_read(0x6064, 0), target)  # getPosition
        self.assertEqual(c.simple_read(0x6041, 0, signed=False), 0x0427)
        if not async_messages:
            self.assertEqual(c.port.in_waiting, 0, "nothing unasked with asynchronous messages off")

    def test_mc5005_pattern_with_asynchronous_messages_off(self):
        self.session(async_messages=False)

    def test_mc5005_pattern_with_asynchronous_messages_on(self):
        self.session(async_messages=True)


class PtyLifecycle(unittest.TestCase):
    def test_closing_and_reopening_the_pty_does_not_touch_the_drive(self):
        with tempfile.TemporaryDirectory() as tmp:
            link = os.path.join(tmp, "ttyFH")
            with Mcemu(*FH, "--faulhaber-pty", link) as m:
                c = fc.open_pty(link)
                c.sdo_write(0x6060, 0, 1, 1)
                for cw in (0x06, 0x0F):
                    self.assertEqual(c.controlword(cw), 0)
                c.sdo_write(0x607A, 0, 200000, 4)
                c.controlword(0x1F)
                c.close()  # mid-move
                wait_for(lambda: m.read_object(0x6064, 0) > 1000, what="the move goes on")
                self.assertEqual(m.read_object(0x6041, 0) & 0x6F, 0x27, "still Operation enabled")
                wait_for(lambda: target_reached_via_http(m, 200000), timeout=30, what="move finished")
                # the next program that opens the port is served; nothing stale is waiting for it
                c = fc.open_pty(link)
                try:
                    self.assertEqual(c.port.in_waiting, 0)
                    self.assertEqual(c.statusword() & 0x6F, 0x27)
                    self.assertEqual(c.position(), 200000)
                finally:
                    c.close()
                self.assertTrue(os.path.islink(link))
            self.assertFalse(os.path.lexists(link), "the symlink is removed at exit")
            self.assertIn("listening: faulhaber pty", m.log())

    def test_symlink_removed_at_exit_after_sigint(self):
        import signal
        with tempfile.TemporaryDirectory() as tmp:
            link = os.path.join(tmp, "ttyFH")
            m = Mcemu(*FH, "--faulhaber-pty", link)
            try:
                self.assertTrue(os.path.islink(link))
                target = os.readlink(link)
                self.assertTrue(target.startswith("/dev/pts/"), target)
            finally:
                self.assertEqual(m.terminate(signal.SIGINT), 0)
                m.__exit__(None, None, None)
            self.assertFalse(os.path.lexists(link))


class OneShot:
    """A fresh connection per request (needs self.m and self.port)."""

    def one_shot(self, request, answer_len, split_at=None):
        """A fresh connection per request; the request is sent in two writes split at `split_at`."""
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            if split_at is None:
                s.sendall(request)
            else:
                s.sendall(request[:split_at])
                time.sleep(0.001)  # two TCP segments in practice (the receiver may not depend on it)
                s.sendall(request[split_at:])
            try:
                return recv_exactly(s, answer_len)
            except (socket.timeout, TimeoutError):
                events = json.loads(self.m.http("GET", "/api/v1/trace?channels=faulhaber&limit=10000")[1])["events"]
                tail = [f'{e["timeMs"]} {e["conn"]} {e["dir"]} {e["text"]}' for e in events[-10:]]
                raise AssertionError(f"no answer to {request.hex(' ')} split at {split_at}; trace:\n" + "\n".join(tail))

class TcpManualClock(OneShot, unittest.TestCase):
    """Requests and responses need no drive time: under --clock manual the drive time stands still
    between two TCP segments, so the 50 ms inter-byte timeout of §4 cannot fire whatever the host's
    load, and it can be tested exactly by advancing the clock."""

    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu(*FH, "--clock", "manual")
        cls.port = cls.m.ports["faulhaber"]

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def advance(self, ms):
        st, body = self.m.http("POST", "/api/v1/clock/advance", {"ms": ms})
        self.assertEqual(st, 200, body)

    def setUp(self):
        self.assertEqual(self.m.http("POST", "/api/v1/power-cycle", {})[0], 200)
        self.advance(10)  # out of Not ready to switch on
        self.assertEqual(self.one_shot(READ_6041, len(ANSWER_6041_0040)), ANSWER_6041_0040)

    def test_example_table_over_tcp(self):
        for request, answer in ((READ_6041, ANSWER_6041_0040), (READ_1234, ERROR_1234), (WRITE_6041, ERROR_6041),
                                (WRITE_6060_3, ANSWER_WRITE_6060),
                                (READ_3005_09, fc.frame(1, 1, bytes.fromhex("05 30 09 00 00 00 00"))),
                                (CW_COMMAND_06, CW_ANSWER_OK + SW_0021)):
            with self.subTest(request=request.hex(" ")):
                self.assertEqual(self.one_shot(request, len(answer)), answer)

    def test_fresh_client_per_request_split_at_every_byte_offset(self):
        cases = [
            (READ_6041, ANSWER_6041_0040),
            (READ_1234, ERROR_1234),
            (WRITE_6041, ERROR_6041),
            # the 6064h answer of §3 carries its CRC 0x53 = `S`; the name read carries the boot text
            (fc.sdo_read_frame(1, 0x1008, 0), fc.frame(1, 1, bytes.fromhex("08 10 00") + b"MC 5005")),
            (fc.sdo_write_frame(1, 0x3005, 0x09, -1, 4), fc.frame(1, 2, bytes.fromhex("05 30 09"))),
            (fc.sdo_read_frame(1, 0x3005, 0x09), bytes.fromhex("53 0B 01 01 05 30 09 FF FF FF FF 9D 45")),
        ]
        n = 0
        for request, answer in cases:
            for k in range(1, len(request)):
                with self.subTest(request=request.hex(" "), split=k):
                    self.assertEqual(self.one_shot(request, len(answer), split_at=k), answer)
                    n += 1
        self.assertEqual(n, sum(len(r) - 1 for r, _ in cases))

    def test_inter_byte_timeout(self):
        for gap, answered in ((50, True), (51, False)):
            with self.subTest(gap=gap), socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
                s.sendall(READ_6041[:4])
                self.advance(gap)
                s.sendall(READ_6041[4:])
                if answered:
                    self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040)), ANSWER_6041_0040)
                else:
                    self.assertTrue(nothing_more(s), "a partial frame older than 50 ms is dropped")
                    s.sendall(READ_6041)  # the next frame starts afresh
                    self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040)), ANSWER_6041_0040)

    def test_stray_sof_with_a_long_length_costs_one_timeout(self):
        # `S` + L = 0x40 in noise swallows what follows until 66 bytes or 50 ms have passed; the
        # host's retry after its time-out is answered (faulhaber.md §4 steps 3 and 5)
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(b"S\x40" + READ_6041)
            self.assertTrue(nothing_more(s))
            self.advance(60)
            s.sendall(READ_6041)
            self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040)), ANSWER_6041_0040)
            self.assertTrue(nothing_more(s))


class Tcp(OneShot, unittest.TestCase):
    """Over TCP with a plain socket where bytes matter, and with pyserial's socket:// otherwise."""

    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu(*FH)
        cls.port = cls.m.ports["faulhaber"]

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def setUp(self):
        # every test starts from a freshly powered drive (factory 0x2400: EMCY and asynchronous
        # messages on, no net mode; Switch on disabled) and one connected observer
        self.assertEqual(self.m.http("DELETE", "/api/v1/faults")[0], 200)
        self.assertEqual(self.m.http("POST", "/api/v1/power-cycle", {})[0], 200)
        self.client = fc.open_tcp(self.port)
        self.assertEqual(self.client.statusword(), 0x0040)
        # Switch on disabled follows the boot message a step later and goes to every connection: a
        # client that connected within that step has it, before the response that already reads
        # 0x0040. Nothing else may be there.
        seen = [(f.command, f.statusword if f.command == fc.STATUSWORD else None) for f in self.client.notifications]
        self.assertIn(seen, ([], [(fc.STATUSWORD, 0x40)]))
        self.client.notifications.clear()

    def tearDown(self):
        self.client.close()

    def test_noise_before_a_good_frame(self):
        noises = [
            b"\x00\x01\x02\xff\xfeEEE",  # no `S` at all
            b"S\x02",  # a stray S with L < 4
            b"S\x05\x01\x01\x00\x00\x00",  # a complete-looking frame without E
            b"\x45S\x09",  # a stray S whose L runs into the good frame and ends on no E
            b"hello world\r\nS\x03\x00",
        ]
        for noise in noises:
            with self.subTest(noise=noise):
                self.assertEqual(self.one_shot(noise + READ_6041, len(ANSWER_6041_0040)), ANSWER_6041_0040)
        # the same on one connection, everything in one segment: only the good frames are answered
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(b"".join(n + READ_6041 for n in noises))
            self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040) * len(noises)), ANSWER_6041_0040 * len(noises))
            self.assertTrue(nothing_more(s))

    def test_wrong_crc_ignored_and_the_next_good_frame_answered(self):
        bad = bytearray(WRITE_6040_06)
        bad[-2] ^= 0x01
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(bytes(bad))
            self.assertTrue(nothing_more(s), "no answer to a wrong CRC")
            s.sendall(bytes(bad) + READ_6041)
            self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040)), ANSWER_6041_0040)
            self.assertTrue(nothing_more(s))
        self.assertEqual(self.client.statusword(), 0x0040, "the bad controlword write changed nothing")
        # with 0x2400.04 bit 23 set the CRC is not checked
        self.client.sdo_write(0x2400, 0x04, 0x00830000, 4)
        try:
            garbled = bytearray(READ_6041)
            garbled[-2] = 0x00
            self.assertEqual(self.one_shot(bytes(garbled), len(ANSWER_6041_0040)), ANSWER_6041_0040)
        finally:
            self.client.sdo_write(0x2400, 0x04, 0x00030000, 4)

    def test_unknown_command_answers_05040001(self):
        for command, data in ((0x20, bytes.fromhex("41 60 00")), (0x06, b""), (0x08, bytes.fromhex("08 10 00")),
                              (0x7F, b"\x01")):
            with self.subTest(command=command):
                request = fc.frame(1, command, data)
                index_sub = data if len(data) >= 3 else b"\x00\x00\x00"
                answer = fc.frame(1, 3, index_sub[:3] + (0x05040001).to_bytes(4, "little"))
                self.assertEqual(self.one_shot(request, len(answer)), answer)

    def test_other_node_ignored(self):
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(fc.sdo_read_frame(2, 0x6041, 0) + fc.controlword_frame(2, 0x06))
            self.assertTrue(nothing_more(s))
            s.sendall(READ_6041)
            self.assertEqual(recv_exactly(s, len(ANSWER_6041_0040)), ANSWER_6041_0040)
        self.assertEqual(self.client.statusword(), 0x0040)

    def test_statusword_notifications_follow_the_response(self):
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            s.sendall(CW_COMMAND_06)
            self.assertEqual(recv_exactly(s, len(CW_ANSWER_OK) + len(SW_0021)), CW_ANSWER_OK + SW_0021)
            s.sendall(CW_COMMAND_0F)
            got = recv_exactly(s, len(CW_ANSWER_OK) + len(SW_0027))
            self.assertEqual(got, CW_ANSWER_OK + SW_0027)
            # bit 10 (target reached, at rest) follows in a later step: one more notification
            self.assertEqual(recv_exactly(s, len(SW_0427)), SW_0427)
            s.sendall(fc.sdo_write_frame(1, 0x6040, 0, 0x0000, 2))  # the same by SDO write: response first
            self.assertEqual(recv_exactly(s, len(ANSWER_WRITE_6040) + len(SW_0040)), ANSWER_WRITE_6040 + SW_0040)
            self.assertTrue(nothing_more(s))
        # the asynchronous messages went to every connection: the other client saw them too
        self.client.drain(0.1)
        self.assertEqual([f.statusword for f in self.client.notifications], [0x21, 0x27, 0x427, 0x40])

    def test_async_switches_and_net_mode(self):
        c = self.client
        c.sdo_write(0x2400, 0x04, 0x00010000, 4)  # EMCY only: no statusword notifications
        c.controlword(0x06)
        c.controlword(0x00)
        self.assertEqual(c.drain(0.1), [])
        c.sdo_write(0x2400, 0x04, 0x00030000, 4)
        c.sdo_write(0x2400, 0x05, 1, 1)  # net mode: responses only
        self.assertEqual(c.controlword(0x06), 0)
        self.assertEqual(c.statusword(), 0x21)
        c.controlword(0x00)
        self.assertEqual(c.drain(0.1), [], "no notifications in net mode")
        with self.assertRaises(fc.SdoError) as e:
            c.sdo_write(0x2400, 0x05, 2, 1)
        self.assertEqual(e.exception.code, 0x06090030)
        with self.assertRaises(fc.SdoError) as e:
            c.sdo_write(0x2400, 0x04, 1, 1)  # a 1-byte write of the U32
        self.assertEqual(e.exception.code, 0x06070013)
        # net mode stored: no boot message after a power cycle either
        try:
            self.assertEqual(self.m.http("POST", "/api/v1/store", {})[0], 200)
            self.assertEqual(self.m.http("POST", "/api/v1/power-cycle", {})[0], 200)
            self.assertEqual(c.read_int(0x2400, 0x05), 1)
            self.assertEqual(c.drain(0.2), [], "no boot message in net mode")
        finally:
            self.assertEqual(self.m.http("POST", "/api/v1/factory-reset", {})[0], 200)
        self.assertEqual(c.read_int(0x2400, 0x05), 0)

    def test_boot_message_after_power_cycle_and_reset_node(self):
        c = self.client
        st, _ = self.m.http("POST", "/api/v1/power-cycle", {})
        self.assertEqual(st, 200)
        boot = c.wait_notification(lambda f: f.command == fc.BOOT, what="boot message")
        self.assertEqual(boot.raw, BOOT_MC5005)
        # Switch on disabled follows a step after the boot message and goes to every connection:
        # wait for it, so that a client connecting next cannot race it
        sw = c.wait_notification(lambda f: f.command == fc.STATUSWORD, what="statusword after boot")
        self.assertEqual(sw.statusword, 0x40)
        # a client that connects now gets nothing on connect
        with socket.create_connection(("127.0.0.1", self.port), timeout=5) as s:
            self.assertTrue(nothing_more(s))
            # no direct response: the boot message, then Switch on disabled (transition 1, a step later)
            for reset in (RESET_NODE, fc.frame(1, 0, b"\x12\x34")):  # L = 4, and L = 6 as the AN191 library sends
                s.sendall(reset)
                self.assertEqual(recv_exactly(s, len(BOOT_MC5005) + len(SW_0040)), BOOT_MC5005 + SW_0040)
        c.drain(0.1)
        self.assertEqual(sum(1 for f in c.notifications if f.command == fc.BOOT), 2, "to every connection")
        # the reset really reset the drive: enable, reset, disabled again
        c.notifications.clear()
        c.controlword(0x06)
        c.send(RESET_NODE)
        c.wait_notification(lambda f: f.command == fc.BOOT, what="boot message")
        # the boot message ends the initialisation; Switch on disabled follows (transition 1)
        c.wait_notification(lambda f: f.command == fc.STATUSWORD and f.statusword == 0x40, what="0x0040")
        self.assertEqual(c.statusword(), 0x40)

    def test_emcy_on_injected_fault_and_its_reset(self):
        c = self.client
        st, body = self.m.http("POST", "/api/v1/faults", {"kind": "drive.inject", "cause": "under_voltage"})
        self.assertEqual(st, 201, body)
        emcy = c.wait_notification(lambda f: f.command == fc.EMCY, what="EMCY")
        # 3220h, register = voltage class (bit 2) + generic (bit 0), 2320h bit 3 (faulhaber.md §7.3)
        self.assertEqual(emcy.raw, fc.frame(1, 7, bytes.fromhex("20 32 05 08 00 00 00 00")))
        self.assertEqual(emcy.emcy, (0x3220, 0x05, 0x0008))
        c.wait_notification(lambda f: f.command == fc.STATUSWORD and f.statusword & 0x4F == 0x08, what="Fault")
        self.assertEqual(c.read_int(0x2320, 0, signed=False), 0x0008)
        self.assertEqual(c.read_int(0x1001, 0, signed=False), 0x05)
        st, _ = self.m.http("DELETE", "/api/v1/faults")
        self.assertEqual(st, 200)
        self.assertEqual(c.controlword(0x80), 0)  # fault reset
        reset = c.wait_notification(lambda f: f.command == fc.EMCY, what="error reset EMCY")
        self.assertEqual(reset.raw, EMCY_ERROR_RESET)
        c.wait_notification(lambda f: f.command == fc.STATUSWORD and f.statusword == 0x40, what="Switch on disabled")
        # EMCY off (bit 16 clear): the same fault raises no EMCY, the statusword still notifies
        c.sdo_write(0x2400, 0x04, 0x00020000, 4)
        self.m.http("POST", "/api/v1/faults", {"kind": "drive.inject", "cause": "under_voltage"})
        c.wait_notification(lambda f: f.command == fc.STATUSWORD and f.statusword & 0x4F == 0x08, what="Fault")
        self.m.http("DELETE", "/api/v1/faults")
        c.controlword(0x00)
        c.controlword(0x80)  # a fault reset is the rising edge of bit 7
        c.wait_notification(lambda f: f.command == fc.STATUSWORD and f.statusword == 0x40, what="reset")
        self.assertFalse([f for f in c.notifications if f.command == fc.EMCY])

    def test_closed_connection_has_no_effect_on_the_drive(self):
        c = self.client
        c.sdo_write(0x6060, 0, 1, 1)
        c.controlword(0x06)
        c.controlword(0x0F)
        other = fc.open_tcp(self.port)
        other.sdo_write(0x607A, 0, 100000, 4)
        other.controlword(0x1F)
        # half a request, then gone (also: an abrupt reset)
        other.send(READ_6041[:4])
        other.port._socket.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
        other.close()
        wait_for(lambda: c.position() > 1000, what="the move goes on")
        self.assertEqual(c.statusword() & 0x6F, 0x27)
        deadline = time.monotonic() + 30
        while not (c.statusword() & 0x400 and c.position() == 100000):
            self.assertLess(time.monotonic(), deadline)
        c.controlword(0x00)
        c.sdo_write(0x607A, 0, 0, 4)

    def trace_end(self):
        """The `since` that skips every event recorded so far (the endpoint pages from the oldest)."""
        since = 0
        while True:
            body = json.loads(self.m.http("GET", f"/api/v1/trace?channels=faulhaber&since={since}&limit=10000")[1])
            if not body["events"]:
                return since
            since = body["nextSeq"]

    def test_trace_channel_shows_both_directions_with_a_summary(self):
        since = self.trace_end()
        self.client.statusword()
        with self.assertRaises(fc.SdoError):
            self.client.sdo_read(0x1234, 0)
        st, body = self.m.http("GET", f"/api/v1/trace?channels=faulhaber&since={since}")
        self.assertEqual(st, 200)
        events = json.loads(body)["events"]
        texts = [(e["dir"], e["text"]) for e in events if e["channel"] == "faulhaber"]
        self.assertLess(len(texts), 20, texts)
        self.assertIn(("rx", "53 07 01 01 41 60 00 73 45 | SDO read 6041.00"), texts)
        self.assertIn(("tx", "53 09 01 01 41 60 00 40 00 C2 45 | SDO read 6041.00 → 0x0040"), texts)
        rx_1234 = [t for d, t in texts if d == "rx" and t.startswith("53 07 01 01 34 12 00 8B 45")]
        tx_1234 = [t for d, t in texts if d == "tx" and t.startswith("53 0B 01 03 34 12 00 00 00 02 06 2B 45")]
        self.assertEqual(len(rx_1234), 1)
        self.assertEqual(len(tx_1234), 1)
        self.assertIn("06020000", tx_1234[0].replace(" ", "").upper())
        self.assertTrue(all("peer" in e and "conn" in e for e in events if e["dir"] in ("rx", "tx")))
        # the text export carries them too
        st, body = self.m.http("GET", f"/api/v1/trace/text?channels=faulhaber&since={since}")
        self.assertEqual(st, 200)
        self.assertIn("SDO read 6041.00", body.decode())

    def test_info_names_the_personality_and_ports(self):
        st, body = self.m.http("GET", "/api/v1/info")
        self.assertEqual(st, 200)
        info = json.loads(body)
        self.assertEqual(info["personality"], "faulhaber")
        self.assertEqual(info["model"], "FH_MC5005")
        self.assertEqual(info["deviceName"], "MC 5005")
        self.assertEqual(info["ports"]["faulhaber"], self.port)
        self.assertEqual(info["ports"]["http"], self.m.ports["http"])
        self.assertNotIn("refgo", info["ports"])
        self.assertNotIn("slcan", info["ports"])
        self.assertEqual(set(self.m.ports), {"faulhaber", "http"}, "no RefGo, SLCAN or UDP listener")


class Limits(unittest.TestCase):
    def test_max_clients(self):
        # --max-clients (every port) and the port's own config key faulhaber.max_clients
        cfg = config_file({"faulhaber": {"max_clients": 2}})
        try:
            for args in (("--max-clients", "2"), ("--config", cfg)):
                with self.subTest(args=args[0]):
                    self._limit_of_two(args)
        finally:
            os.unlink(cfg)

    def _limit_of_two(self, args):
        with Mcemu(*FH, *args) as m:
            port = m.ports["faulhaber"]
            a, b = fc.open_tcp(port), fc.open_tcp(port)
            try:
                self.assertEqual(a.statusword(), 0x40)
                self.assertEqual(b.statusword(), 0x40)
                with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
                    try:
                        s.sendall(READ_6041)
                        got = s.recv(100)
                    except (ConnectionResetError, BrokenPipeError):  # closed with the request unread: RST, not FIN
                        got = b""
                    self.assertEqual(got, b"", "the third connection is closed at once without a byte")
                self.assertEqual(a.statusword(), 0x40)
                b.close()
                # a slot is free again
                c = wait_for(lambda: self._served(port), what="a new client served after one left")
                c.close()
            finally:
                a.close()
                b.close()

    @staticmethod
    def _served(port):
        c = fc.open_tcp(port, timeout=0.5)
        try:
            c.statusword()
            return c
        except (TimeoutError, OSError, AssertionError):
            c.close()
            return None


class Fleets(unittest.TestCase):
    def test_fleet_mixing_a_movingcap_and_a_faulhaber_drive(self):
        fleet = config_file([{"model": "MC349"}, {"model": "FH_MC5005", "faulhaber": {"serial": 42}}])
        try:
            with Mcemu("--fleet", fleet) as m:
                wait_for(lambda: len(m.drives) == 2 and "faulhaber" in m.drives[2], what="listeners")
                self.assertEqual(set(m.drives[1]), {"refgo", "slcan", "http", "udp"})
                self.assertEqual(set(m.drives[2]), {"faulhaber", "http"})
                address, port = m.drives[1]["refgo"]
                with socket.create_connection((address, port), timeout=5) as s:
                    s.sendall(b"OR1018,4\r")
                    data = b""
                    while not data.endswith(b">"):
                        data += s.recv(100)
                    self.assertTrue(data.startswith(b"OR1018,4\r\nOR1018,4,"), data)
                    # the MovingCap's RefGo port does not speak FAULHABER frames
                address, port = m.drives[2]["faulhaber"]
                self.assertEqual(address, "127.0.0.2")
                c = fc.open_tcp(port, host=address)
                try:
                    self.assertEqual(c.read_int(0x1018, 4), 42)
                    self.assertEqual(c.read_string(0x1008, 0), "MC 5005")
                    self.assertEqual(c.read_int(0x1018, 1), 0x147)
                finally:
                    c.close()
                self.assertEqual(json.loads(m.http("GET", "/api/v1/info", drive=1)[1])["personality"], "movingcap")
                self.assertEqual(json.loads(m.http("GET", "/api/v1/info", drive=2)[1])["personality"], "faulhaber")
        finally:
            os.unlink(fleet)

    def test_two_faulhaber_drives_with_port_step(self):
        for _ in range(5):
            with socket.socket() as probe:
                probe.bind(("127.0.0.1", 0))
                base = probe.getsockname()[1]
            if base + 10 > 65535:
                continue
            m = Mcemu("--model", "FH_MC5005", "--drives", "2", "--port-step", "10", "--faulhaber-port", str(base),
                      "--http-port", "0", ports_zero=False, ready=False)
            try:
                wait_for(lambda: m.has_line("ready") or m.proc.poll() is not None, what="ready")
                if m.proc.poll() is not None:
                    continue  # a port was taken meanwhile: another base
                wait_for(lambda: len(m.drives) == 2 and all("faulhaber" in d for d in m.drives.values()),
                         what="two FAULHABER listeners")
                self.assertEqual(m.drives[1]["faulhaber"], ("127.0.0.1", base))
                self.assertEqual(m.drives[2]["faulhaber"], ("127.0.0.1", base + 10))
                a, b = fc.open_tcp(base), fc.open_tcp(base + 10)
                try:
                    # as a host does after power-on: wait for Switch on disabled (on a loaded machine
                    # drive 1 may still be initialising when the process reports ready)
                    wait_for(lambda: a.statusword() == 0x40 and b.statusword() == 0x40, what="Switch on disabled")
                    a.controlword(0x06)
                    self.assertEqual(a.statusword(), 0x21)
                    self.assertEqual(b.statusword(), 0x40, "drive 2 is its own drive")
                finally:
                    a.close()
                    b.close()
                return
            finally:
                m.__exit__(None, None, None)
        self.fail("no free pair of ports found")


if __name__ == "__main__":
    unittest.main()
