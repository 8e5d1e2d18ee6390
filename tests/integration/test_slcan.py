"""CANopen node 50 over SLCAN on TCP (issue 5): the real mcemu binary on port 0, python-can 4.1's
`slcan` interface over `socket://` as the client (the cases marked ★ in slcan-canopen.md §12), plus
raw-socket checks of the byte stream (§3). Exact simulated times are asserted at unit level; here
the frames, their bytes and their order."""
import json
import os
import struct
import subprocess
import time
import unittest

from mcemu_harness import MCEMU, Mcemu, wait_for
from slcan_client import SIZES, Client, Raw, SdoAbort, crc16
from test_xdd_conformance import XDD_DIR, xdd_entries


def dump(model):
    r = subprocess.run([MCEMU, "--dump-od", "--model", model], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)["entries"]


def stamped_frames(raw, predicate, count, timeout=10.0):
    """Reads the frame lines of a session that sent Z1 until `count` lines match `predicate`;
    returns the matching (line, drive-time stamp in ms modulo 60000). Every line read is kept in
    raw.seen as (line, stamp)."""
    if not hasattr(raw, "seen"):
        raw.seen, raw.partial = [], b""
    found = []
    deadline = time.monotonic() + timeout
    while len(found) < count:
        if time.monotonic() > deadline:
            raise TimeoutError(f"{len(found)} of {count} frames; last lines {raw.seen[-5:]!r}")
        raw.partial += raw.read_until(lambda b: b"\r" in b, timeout=max(0.1, deadline - time.monotonic()))
        *lines, raw.partial = raw.partial.split(b"\r")
        for line in lines:
            if not line.startswith(b"t"):
                continue
            entry = (line[:-4], int(line[-4:], 16))
            raw.seen.append(entry)
            if predicate(entry[0]):
                found.append(entry)
    return found


class Base(unittest.TestCase):
    args = ()

    def setUp(self):
        self.mcemu = Mcemu(*self.args)
        self.port = self.mcemu.ports["slcan"]
        self.clients = []

    def tearDown(self):
        for c in self.clients:
            try:
                c.close()
            except Exception:  # noqa: BLE001 - a test may have closed it
                pass
        self.mcemu.__exit__(None, None, None)

    def client(self, **kwargs):
        c = Client(self.port, **kwargs)
        self.clients.append(c)
        return c

    def raw(self):
        r = Raw(self.port)
        self.clients.append(r)
        return r


class OpenAndRead(Base):
    def test_python_can_opens_the_bus_with_and_without_bitrate(self):
        c = self.client()
        self.assertEqual(c.upload(0x6041, 0), b"\x40\x00")
        c2 = self.client(bitrate=125000)  # 4.1 sends C, S4, O, O
        self.assertEqual(c2.upload(0x1000, 0), struct.pack("<I", 0x00020192))
        self.assertNotIn("error", self.mcemu.log().lower())

    def test_od01_every_readable_xdd_entry_with_the_right_size(self):  # OD-01 ★
        c = self.client()
        _, xdd = xdd_entries(os.path.join(XDD_DIR, "MC349_ETH.xdd"))
        entries = {(e["index"], e["sub"]): e for e in dump("MC349")}
        checked = 0
        for (index, sub), (dtype, access) in sorted(xdd.items()):
            if access == "wo":
                continue
            data = c.upload(index, sub)
            e = entries[(index, sub)]
            if dtype == "VISIBLE_STRING":
                self.assertEqual(data.decode(), e["value"], f"{index:04X}.{sub:02X}")
            else:
                self.assertEqual(len(data), SIZES[dtype], f"{index:04X}.{sub:02X}")
                if e["class"] != "live":
                    value = int.from_bytes(data, "little", signed=dtype.startswith("INTEGER"))
                    self.assertEqual(value, e["value"], f"{index:04X}.{sub:02X}")
            checked += 1
        # and the mcemu additions (1400h on MC349, 3500h.03–.06, 3510h, 5006h, 6062h, 60B8h)
        for (index, sub), e in entries.items():
            if (index, sub) not in xdd:
                data = c.upload(index, sub)
                if e["type"] != "VISIBLE_STRING":
                    self.assertEqual(len(data), SIZES[e["type"]])
                checked += 1
        self.assertEqual(checked, len(entries))

    def test_od09_identity(self):
        c = self.client()
        self.assertEqual(c.upload(0x1000, 0), struct.pack("<I", 0x00020192))
        self.assertEqual(c.upload(0x1018, 1), struct.pack("<I", 0x053B))
        self.assertEqual(c.upload(0x1018, 2), struct.pack("<I", 50))
        self.assertEqual(c.upload(0x1008, 0), b"MC349_ETH_RE")
        self.assertEqual(c.upload(0x100A, 0), b"v50.00.10.00_RE")
        self.assertEqual(c.upload(0x1200, 1), struct.pack("<I", 0x632))
        self.assertEqual(c.upload(0x1200, 2), struct.pack("<I", 0x5B2))


class Transfers(Base):
    def test_sdo01_02_expedited_upload_and_download(self):  # SDO-01 ★, SDO-02 ★
        c = self.client()
        self.assertEqual(c.sdo(bytes.fromhex("4061600000000000")), bytes.fromhex("4F61600000000000"))
        self.assertEqual(c.sdo(bytes.fromhex("4041600000000000")), bytes.fromhex("4B41600040000000"))
        self.assertEqual(c.sdo(bytes.fromhex("4018100100000000")), bytes.fromhex("431810013B050000"))
        for index, sub, data in ((0x6060, 0, b"\x03"), (0x6083, 0, struct.pack("<I", 2500)),
                                 (0x1017, 0, struct.pack("<H", 0)), (0x607A, 0, struct.pack("<i", -5000))):
            c.download(index, sub, data)
            self.assertEqual(c.upload(index, sub), data)
        self.assertEqual(c.sdo(bytes.fromhex("2F60600001000000")), bytes.fromhex("6060600000000000"))

    def test_sdo04_segmented_uploads_of_the_strings(self):  # SDO-04 ★, SDO-05
        c = self.client()
        self.assertEqual(c.sdo(bytes.fromhex("4008100000000000")), bytes.fromhex("410810000C000000"))
        self.assertEqual(c.sdo(bytes.fromhex("6000000000000000")), b"\x00MC349_E")
        self.assertEqual(c.sdo(bytes.fromhex("7000000000000000")), b"\x15TH_RE\x00\x00")
        self.assertEqual(c.upload(0x100A, 0), b"v50.00.10.00_RE")
        self.assertEqual(c.upload(0x1009, 0), b"V1.00")
        self.assertEqual(c.upload(0x6403, 0), b"")

    def test_segmented_download(self):  # SDO-06
        c = self.client()
        self.assertEqual(c.sdo(bytes.fromhex("217A600004000000")), bytes.fromhex("607A600000000000"))
        self.assertEqual(c.sdo(bytes.fromhex("0730750000000000")), bytes.fromhex("2000000000000000"))
        self.assertEqual(c.upload(0x607A, 0), struct.pack("<i", 30000))

    def test_sdo15_block_upload_and_sdo21_block_download(self):  # SDO-15 ★, SDO-21 ★
        c = self.client()
        self.assertEqual(c.sdo(bytes.fromhex("A40810007F000000")), bytes.fromhex("C60810000C000000"))
        c.send(0x632, bytes.fromhex("A300000000000000"))
        segs = [c.recv_until(lambda m: m.arbitration_id == 0x5B2) for _ in range(2)]
        self.assertEqual([bytes(m.data) for m in segs], [b"\x01MC349_E", b"\x82TH_RE\x00\x00"])
        self.assertEqual(c.sdo(bytes.fromhex("A2027F0000000000")), bytes.fromhex("C94DA30000000000"))
        c.send(0x632, bytes.fromhex("A100000000000000"))
        self.assertEqual(c.block_upload(0x100A, 0, crc=False), b"v50.00.10.00_RE")
        self.assertEqual(c.sdo(bytes.fromhex("C67A600004000000")), bytes.fromhex("A47A60007F000000"))
        self.assertEqual(c.sdo(bytes.fromhex("8130750000000000")), bytes.fromhex("A2017F0000000000"))
        self.assertEqual(c.sdo(bytes.fromhex("CD111F0000000000")), bytes.fromhex("A100000000000000"))
        self.assertEqual(c.upload(0x607A, 0), struct.pack("<i", 30000))
        c.block_download(0x6083, 0, struct.pack("<I", 1234), crc=False)
        self.assertEqual(c.upload(0x6083, 0), struct.pack("<I", 1234))
        self.assertEqual(crc16(b"MC349_ETH_RE"), 0xA34D)

    def test_block_transfers_through_python_can_many_times(self):
        # No object of a shipped model holds 100 kB (strings are read-only and short; slcan-canopen.md
        # §12 SDO-22 runs the 100 kB transfer on a unit-test dictionary): move 100 kB through block
        # transfers of the real objects instead, in both directions.
        c = self.client()
        moved = 0
        value = 0
        while moved < 100 * 1024:
            value += 1
            c.block_download(0x607A, 0, struct.pack("<i", value), crc=value % 2 == 0)
            moved += 4
            moved += len(c.block_upload(0x1008, 0, crc=value % 2 == 1))
        self.assertEqual(c.upload(0x607A, 0), struct.pack("<i", value))

    def test_every_abort_reaches_the_client(self):  # §6.9 over TCP
        c = self.client()
        cases = [
            ("4000200000000000", 0x06020000),  # missing object
            ("2B41600000000000", 0x06010002),  # read-only
            ("4018100500000000", 0x06090011),  # missing sub
            ("2360600001000000", 0x06070012),  # length too high
            ("2F4060000F000000", 0x06070013),  # length too low
            ("2F60600063000000", 0x06090030),  # value not allowed
            ("2F04340380000000", 0x06090031),  # node-id 128
            ("2F04340300000000", 0x06090032),  # node-id 0
            ("E000100000000000", 0x05040001),  # ccs 7
            ("6000000000000000", 0x05040001),  # segment while idle
            ("A408100000000000", 0x05040002),  # blksize 0
            ("2310100153415645", 0x08000020),  # "SAVE"
        ]
        for req, code in cases:
            resp = c.sdo(bytes.fromhex(req))
            self.assertEqual(resp[0], 0x80, req)
            self.assertEqual(resp[1:4], bytes.fromhex(req)[1:4] if code != 0x05040001 or req[0] == "E" else bytes(3))
            self.assertEqual(struct.unpack_from("<I", resp, 4)[0], code, req)
        # toggle error, block CRC error, sequence error and the timeout
        c.sdo(bytes.fromhex("4008100000000000"))
        c.sdo(bytes.fromhex("6000000000000000"))
        self.assertEqual(c.sdo(bytes.fromhex("6000000000000000")), bytes.fromhex("8008100000000305"))
        c.sdo(bytes.fromhex("C67A600004000000"))
        c.sdo(bytes.fromhex("8130750000000000"))
        self.assertEqual(c.sdo(bytes.fromhex("CD121F0000000000")), bytes.fromhex("807A600004000405"))
        c.sdo(bytes.fromhex("C67A600004000000"))
        self.assertEqual(c.sdo(bytes.fromhex("0030750000000000")), bytes.fromhex("807A600003000405"))
        c.sdo(bytes.fromhex("4008100000000000"))
        resp = c.recv_until(lambda m: m.arbitration_id == 0x5B2, timeout=3.0)
        self.assertEqual(bytes(resp.data), bytes.fromhex("8008100000000405"))


class Nmt(Base):
    def test_nmt02_03_start_stop_and_pdos(self):  # NMT-02 ★, NMT-03 ★, PDO-03 ★
        c = self.client()
        c.nmt(0x01)
        t1 = c.recv_until(lambda m: m.arbitration_id == 0x1B2)
        t2 = c.recv_until(lambda m: m.arbitration_id == 0x2B2)
        self.assertEqual(bytes(t1.data), b"\x40\x00")
        self.assertEqual(bytes(t2.data), b"\x40\x00\x00")
        c.nmt(0x01)  # again: nothing
        self.assertEqual(c.collect(0.3, lambda m: m.arbitration_id in (0x1B2, 0x2B2, 0x3B2, 0x4B2)), [])
        c.download(0x1017, 0, struct.pack("<H", 100))
        c.nmt(0x02)
        hb = c.recv_until(lambda m: m.arbitration_id == 0x732 and m.data[0] == 0x04)
        self.assertIsNotNone(hb)
        c.send(0x632, bytes.fromhex("4041600000000000"))
        self.assertEqual(c.collect(0.5, lambda m: m.arbitration_id == 0x5B2), [])
        c.nmt(0x80)
        self.assertEqual(c.upload(0x6041, 0), b"\x40\x00")
        hb = c.recv_until(lambda m: m.arbitration_id == 0x732 and m.data[0] == 0x7F)
        self.assertIsNotNone(hb)

    def test_heartbeat_every_1017h_ms(self):  # HB-02 ★
        # The period is checked in drive time, from the Z1 timestamps of a second, raw session (every
        # node frame goes to every session, §3.7), not by counting frames in a wall-clock window.
        c = self.client()
        r = self.raw()
        self.assertEqual(r.exchange(b"Z1\r", b"\r"), b"\r")
        c.download(0x1017, 0, struct.pack("<H", 100))
        stamps = [stamp for _, stamp in stamped_frames(r, lambda line: line.startswith(b"t7321"), count=11)]
        self.assertEqual([(b - a) % 60000 for a, b in zip(stamps, stamps[1:])], [100] * 10)
        c.download(0x1017, 0, struct.pack("<H", 0))
        # No heartbeat may follow the response to that download (frames reach a session in the
        # node's order), while drive time goes on for three periods (seen in SDO responses).
        stopped_at = stamped_frames(r, lambda line: line.startswith(b"t5B2860171000"), count=1)[-1][1]
        after = len(r.seen)
        while True:
            c.upload(0x6041, 0)
            stamp = stamped_frames(r, lambda line: line.startswith(b"t5B284B4160"), count=1)[-1][1]
            if (stamp - stopped_at) % 60000 >= 300:
                break
        self.assertEqual([l for l, _ in r.seen[after:] if l.startswith(b"t7321")], [], "a heartbeat after 1017h := 0")

    def test_grd01_guarding(self):  # GRD-01 ★
        c = self.client()
        replies = []
        for _ in range(3):
            c.send(0x732, rtr=True, dlc=1)
            replies.append(bytes(c.recv_until(lambda m: m.arbitration_id == 0x732).data))
        self.assertEqual(replies, [b"\x7f", b"\xff", b"\x7f"])

    def test_reset_node_and_communication_keep_the_connection(self):  # NMT-05/06 over TCP
        c = self.client()
        c.download(0x1017, 0, struct.pack("<H", 1000))
        c.nmt(0x82)
        boot = c.recv_until(lambda m: m.arbitration_id == 0x732 and m.data[0] == 0x00)
        self.assertIsNotNone(boot)
        self.assertEqual(c.upload(0x1017, 0), b"\x00\x00")  # reloaded from the factory image
        c.download(0x6083, 0, struct.pack("<I", 777))
        c.nmt(0x81, node=0)
        boot = c.recv_until(lambda m: m.arbitration_id == 0x732 and m.data[0] == 0x00)
        self.assertIsNotNone(boot)
        self.assertEqual(c.upload(0x6083, 0), struct.pack("<I", 1000))  # image rebuilt
        wait_for(lambda: self.mcemu.has_line("NMT reset node"), what="the reset-node log line")


class Pdo(Base):
    def test_pdo20_rpdo2_and_pdo26_rpdo1(self):  # PDO-20 ★, PDO-26 ★
        c = self.client()
        c.nmt(0x01)
        c.send(0x332, bytes.fromhex("0F0001"))
        wait_for(lambda: c.upload(0x6060, 0) == b"\x01", timeout=2, what="6060h = 1")
        self.assertEqual(c.upload(0x6040, 0), b"\x0f\x00")
        self.assertEqual(c.upload(0x1400, 1), struct.pack("<I", 0x232))
        c.send(0x232, bytes.fromhex("0600"))
        wait_for(lambda: c.upload(0x6040, 0) == b"\x06\x00", timeout=2, what="6040h = 6")
        c.download(0x1400, 1, struct.pack("<I", 0x80000232))  # disabled
        c.send(0x232, bytes.fromhex("0700"))
        self.assertEqual(c.upload(0x6040, 0), b"\x06\x00")

    def test_pdo10_rtr_tpdo3(self):  # PDO-10 ★ at rest
        c = self.client()
        c.nmt(0x01)
        c.send(0x3B2, rtr=True, dlc=6)
        t3 = c.recv_until(lambda m: m.arbitration_id == 0x3B2 and not m.is_remote_frame)
        self.assertEqual(len(t3.data), 6)
        self.assertEqual(bytes(t3.data[:2]), c.upload(0x6041, 0))

    def test_pdo02_controlword_by_sdo_then_tpdos(self):  # PDO-02 ★, §9.4 example
        r = self.raw()
        r.exchange(b"t00020132\r", b"z\rt1B224000\rt2B23400000\r")
        reply = r.exchange(b"t63282B40600006000000\r", b"z\rt5B286040600000000000\rt1B222100\rt2B23210000\r")
        self.assertEqual(reply, b"z\rt5B286040600000000000\rt1B222100\rt2B23210000\r")

    def test_rpdo_length_emcy(self):  # PDO-23 over TCP, §7.4 "RPDO too short"
        c = self.client()
        c.nmt(0x01)
        c.send(0x232, b"\x0f")
        emcy = c.recv_until(lambda m: m.arbitration_id == 0x0B2)
        self.assertEqual(bytes(emcy.data), bytes.fromhex("1082110000000000"))
        c.send(0x232, b"\x00\x00")
        emcy = c.recv_until(lambda m: m.arbitration_id == 0x0B2)
        self.assertEqual(bytes(emcy.data), bytes.fromhex("0000000000000000"))

    def test_profile_position_move_over_pdos(self):  # PDO-27 ★: enable and move by RPDO, observed by TPDO
        c = self.client()
        c.nmt(0x01)
        c.recv_until(lambda m: m.arbitration_id == 0x2B2)
        c.send(0x332, bytes.fromhex("000001"))  # RPDO2: controlword 0, mode 1 (profile position)
        c.send(0x232, bytes.fromhex("0600"))  # shutdown
        sw = c.recv_until(lambda m: m.arbitration_id == 0x1B2 and (m.data[0] & 0x6F) == 0x21, timeout=1.0)
        self.assertIsNotNone(sw, "Ready to switch on (0x21) on TPDO1")
        c.send(0x232, bytes.fromhex("0700"))
        self.assertIsNotNone(c.recv_until(lambda m: m.arbitration_id == 0x1B2 and (m.data[0] & 0x6F) == 0x23))
        c.send(0x232, bytes.fromhex("0F00"))
        self.assertIsNotNone(c.recv_until(lambda m: m.arbitration_id == 0x1B2 and (m.data[0] & 0x6F) == 0x27))
        self.assertIsNotNone(c.recv_until(lambda m: m.arbitration_id == 0x2B2 and m.data[2] == 1))
        c.send(0x432, bytes.fromhex("1F0030750000"))  # RPDO3: new set-point, target 30000
        ack = c.recv_until(lambda m: m.arbitration_id == 0x1B2 and m.data[1] & 0x10, timeout=2.0)
        self.assertIsNotNone(ack, "set-point acknowledge (bit 12) on TPDO1")
        self.assertFalse(ack.data[1] & 0x04, "a new set-point clears target reached (bit 10)")
        c.send(0x232, bytes.fromhex("0F00"))
        reached = c.recv_until(lambda m: m.arbitration_id == 0x1B2 and m.data[1] & 0x04, timeout=20.0)
        self.assertIsNotNone(reached, "target reached (bit 10) on TPDO1")
        self.assertFalse([m for m in c.frames if m.arbitration_id == 0x3B2], "TPDO3 (253) only on RTR (PDO-10)")
        c.send(0x3B2, rtr=True, dlc=6)
        t3 = c.recv_until(lambda m: m.arbitration_id == 0x3B2 and not m.is_remote_frame)
        self.assertEqual(struct.unpack_from("<i", bytes(t3.data), 2)[0], 30000)


class Emcy(Base):
    def test_emcy_on_a_fault_and_on_its_reset(self):  # EMCY-02/03 ★ with the life-guarding fault of GRD-04
        c = self.client()
        c.download(0x100C, 0, struct.pack("<H", 100))
        c.download(0x100D, 0, b"\x03")
        c.nmt(0x01)
        c.send(0x732, rtr=True, dlc=1)
        self.assertEqual(bytes(c.recv_until(lambda m: m.arbitration_id == 0x732).data), b"\x05")
        emcy = c.recv_until(lambda m: m.arbitration_id == 0x0B2, timeout=2.0)
        self.assertIsNotNone(emcy, "EMCY of the abort_connection fault")
        self.assertEqual(bytes(emcy.data), bytes.fromhex("3081100000000000"))  # 8130h, register 0x10
        self.assertEqual(c.upload(0x1001, 0), b"\x10")
        self.assertEqual(c.upload(0x603F, 0), struct.pack("<H", 0x8130))
        self.assertEqual(c.upload(0x1003, 1), struct.pack("<I", 0x8130))
        c.nmt(0x80)  # 1029h.01 = 0 already did this; harmless
        c.download(0x6040, 0, struct.pack("<H", 0x0080))  # fault reset edge
        emcy = c.recv_until(lambda m: m.arbitration_id == 0x0B2, timeout=2.0)
        self.assertEqual(bytes(emcy.data), bytes(8))  # 0000h "error reset"
        self.assertEqual(c.upload(0x1001, 0), b"\x00")


class Store(Base):
    def test_restore_refused_in_operation_enabled(self):  # OTH-05 over TCP with the real core and persistence
        c = self.client()
        for cw in (0x06, 0x07, 0x0F):
            c.download(0x6040, 0, struct.pack("<H", cw))
        self.assertEqual(c.upload(0x6041, 0)[0] & 0x6F, 0x27)
        self.assertEqual(c.sdo(bytes.fromhex("231110016C6F6164")), bytes.fromhex("8011100122000008"))
        c.download(0x6040, 0, struct.pack("<H", 0x06))  # shutdown: leaves Operation Enabled after its ramp
        wait_for(lambda: c.upload(0x6041, 0)[0] & 0x6F == 0x21, timeout=5, what="Ready to switch on")
        c.download(0x1017, 0, struct.pack("<H", 300))
        self.assertEqual(c.sdo(bytes.fromhex("231110016C6F6164")), bytes.fromhex("6011100100000000"))
        self.assertEqual(c.upload(0x1017, 0), b"\x00\x00")  # factory values at once (OTH-04)

    def test_oth01_store_survives_a_restart(self):  # OTH-01 ★
        c = self.client()
        c.download(0x1017, 0, struct.pack("<H", 250))
        c.download(0x1800, 5, struct.pack("<H", 40))
        self.assertEqual(c.sdo(bytes.fromhex("2310100173617665")), bytes.fromhex("6010100100000000"))
        state_dir = self.mcemu.state_dir
        c.close()
        self.clients.remove(c)
        self.mcemu.terminate()
        with Mcemu(state_dir=state_dir) as m:
            c2 = Client(m.ports["slcan"])
            try:
                self.assertEqual(c2.upload(0x1017, 0), struct.pack("<H", 250))
                self.assertEqual(c2.upload(0x1800, 5), struct.pack("<H", 40))
                self.assertIsNotNone(c2.recv_until(lambda msg: msg.arbitration_id == 0x732))
            finally:
                c2.close()


class ByteStream(Base):
    def test_malformed_input_gets_bel_and_the_session_continues(self):
        r = self.raw()
        self.assertEqual(r.exchange(b"t63G0\r", b"\a"), b"\a")
        self.assertEqual(r.exchange(b"A" * 100 + b"\r", b"\a"), b"\a")
        self.assertEqual(r.exchange(b"t 0800\rK\rO1\r\x00\r", b"\a\a\a\a"), b"\a\a\a\a")
        self.assertEqual(r.exchange(b"\xff\xfe\r", b"\a"), b"\a")
        self.assertEqual(r.exchange(b"V\rN\rF\r", b"V1010\rN4444\rF00\r"), b"V1010\rN4444\rF00\r")
        reply = r.exchange(b"t63284041600000000000\r", b"z\rt5B284B41600040000000\r")
        self.assertEqual(reply, b"z\rt5B284B41600040000000\r")

    def test_lf_line_ends_and_timestamps(self):
        r = self.raw()
        self.assertEqual(r.exchange(b"V\nF\n", b"V1010\rF00\r"), b"V1010\rF00\r")
        self.assertEqual(r.exchange(b"Z1\r", b"\r"), b"\r")
        reply = r.exchange(b"t63284041600000000000\r", b"z\rt5B284B41600040000000XXXX\r")
        self.assertRegex(reply, rb"^z\rt5B284B41600040000000[0-9A-F]{4}\r$")

    def test_two_clients_share_the_bus(self):  # §3.8 row 33
        a, b = self.raw(), self.raw()
        self.assertEqual(b.exchange(b"F\r", b"F00\r"), b"F00\r")  # B's session exists on the bus
        self.assertEqual(a.exchange(b"t63284041600000000000\r", b"z\rt5B284B41600040000000\r"),
                         b"z\rt5B284B41600040000000\r")
        self.assertEqual(b.read_until(lambda x: len(x) >= 22), b"t5B284B41600040000000\r")
        b.send(b"t0800\r")  # not echoed to A
        self.assertEqual(b.read_until(lambda x: len(x) >= 2), b"z\r")
        a.send(b"F\r")
        self.assertEqual(a.read_until(lambda x: len(x) >= 4), b"F00\r")

    def test_half_close_answers_complete_lines(self):
        r = self.raw()
        r.send(b"V\rt63284041600000000000\rF")
        r.sock.shutdown(1)  # FIN
        data = r.read_until(lambda x: False if len(x) < 30 else True, timeout=3)
        self.assertEqual(data, b"V1010\rz\rt5B284B41600040000000\r")
        self.assertEqual(r.sock.recv(10), b"")  # then mcemu closes


class Config(unittest.TestCase):
    def write_config(self, doc):
        import tempfile
        f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
        json.dump(doc, f)
        f.close()
        self.addCleanup(os.unlink, f.name)
        return f.name

    def test_bad_values_stop_start_up_with_one_line_naming_the_key(self):
        for doc, key in (({"slcan": {"frame_ack": "Z"}}, "slcan.frame_ack"),
                         ({"slcan": {"version": "1.0"}}, "slcan.version"),
                         ({"slcan": {"serial_digits": 6}}, "slcan.serial_digits"),
                         ({"canopen": {"sdo_block_size": 128}}, "canopen.sdo_block_size"),
                         ({"canopen": {"sdo_timeout_ms": 0}}, "canopen.sdo_timeout_ms"),
                         ({"canopen": {"bogus": 1}}, "canopen.bogus")):
            r = subprocess.run([MCEMU, "--config", self.write_config(doc), "--refgo-port", "0", "--slcan-port", "0",
                                "--http-port", "0", "--udp-port", "0"], capture_output=True, text=True, timeout=20)
            self.assertEqual(r.returncode, 2, doc)
            self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
            self.assertIn(key, r.stderr)

    def test_frame_ack_version_serial_and_block_size_settings(self):
        doc = {"slcan": {"frame_ack": "cr", "version": "0042", "serial_digits": 8},
               "canopen": {"sdo_block_size": 5, "sdo_timeout_ms": 200}}
        with Mcemu("--config", self.write_config(doc)) as m:
            r = Raw(m.ports["slcan"])
            try:
                self.assertEqual(r.exchange(b"V\rN\r", b"V0042\rN44444444\r"), b"V0042\rN44444444\r")
                self.assertEqual(r.exchange(b"t6328C67A600004000000\r", b"\rt5B28A47A600005000000\r"),
                                 b"\rt5B28A47A600005000000\r")
                # the 200 ms server timeout ends the transfer
                self.assertEqual(r.read_until(lambda b: len(b) >= 22, timeout=3), b"t5B28807A600000000405\r")
            finally:
                r.close()

    def test_dynamic_pdo_mapping(self):  # §9.7 example over TCP (PDO-29)
        with Mcemu("--config", self.write_config({"canopen": {"dynamic_pdo_mapping": True}})) as m:
            c = Client(m.ports["slcan"])
            try:
                for req, resp in (("23001801B2010080", "6000180100000000"), ("2F001A0000000000", "60001A0000000000"),
                                  ("23001A0120006460", "60001A0100000000"), ("2F001A0001000000", "60001A0000000000"),
                                  ("23001801B2010000", "6000180100000000"), ("23001A0110004160", "80001A0130000906")):
                    self.assertEqual(c.sdo(bytes.fromhex(req)), bytes.fromhex(resp), req)
                c.nmt(0x01)
                t1 = c.recv_until(lambda msg: msg.arbitration_id == 0x1B2)
                self.assertEqual(len(t1.data), 4)
            finally:
                c.close()
        with Mcemu() as m:  # fixed mapping by default
            c = Client(m.ports["slcan"])
            try:
                self.assertEqual(c.sdo(bytes.fromhex("2F001A0000000000")), bytes.fromhex("80001A0002000106"))
            finally:
                c.close()


if __name__ == "__main__":
    unittest.main()
