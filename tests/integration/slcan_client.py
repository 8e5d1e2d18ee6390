"""A CANopen client over python-can's `slcan` interface on `socket://` (python-can 4.1, Debian's
python3-can), as an automation engineer would write it: SDO expedited/segmented/block transfers,
NMT, PDO and EMCY frames. Every wait is bounded; nothing sleeps for a fixed time."""
import socket
import struct
import time

import can

SIZES = {"BOOLEAN": 1, "INTEGER8": 1, "UNSIGNED8": 1, "INTEGER16": 2, "UNSIGNED16": 2, "INTEGER32": 4,
         "UNSIGNED32": 4}


class SdoAbort(Exception):
    def __init__(self, index, sub, code):
        super().__init__(f"SDO abort 0x{code:08X} on {index:04X}h.{sub:02X}h")
        self.index, self.sub, self.code = index, sub, code


def crc16(data, crc=0):
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


class Client:
    """One python-can slcan bus to mcemu, node 50."""

    def __init__(self, port, node=50, address="127.0.0.1", **kwargs):
        self.bus = can.Bus(interface="slcan", channel=f"socket://{address}:{port}", sleep_after_open=0, **kwargs)
        self.node = node
        self.frames = []  # every frame received, in order

    def close(self):
        self.bus.shutdown()

    def send(self, can_id, data=b"", rtr=False, dlc=None):
        msg = can.Message(arbitration_id=can_id, data=bytes(data), is_extended_id=False, is_remote_frame=rtr,
                          dlc=len(data) if dlc is None else dlc)
        self.bus.send(msg)

    def recv_until(self, predicate, timeout=2.0):
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            msg = self.bus.recv(timeout=left)
            if msg is None:
                return None
            self.frames.append(msg)
            if predicate(msg):
                return msg

    def collect(self, duration, predicate=lambda m: True):
        """Every matching frame within `duration` seconds (used to assert that something is absent)."""
        out = []
        deadline = time.monotonic() + duration
        while (left := deadline - time.monotonic()) > 0:
            msg = self.bus.recv(timeout=left)
            if msg is not None:
                self.frames.append(msg)
                if predicate(msg):
                    out.append(msg)
        return out

    # --- SDO ---------------------------------------------------------------------------------
    def sdo(self, request, timeout=10.0):  # a bound for a hang, not a speed check (ASan, parallel CI)
        request = bytes(request) + bytes(8 - len(request))
        self.send(0x600 + self.node, request)
        msg = self.recv_until(lambda m: m.arbitration_id == 0x580 + self.node and not m.is_remote_frame, timeout)
        if msg is None:
            raise TimeoutError(f"no SDO response to {request.hex()}")
        assert msg.dlc == 8, msg
        return bytes(msg.data)

    def _check(self, resp, index, sub):
        if resp[0] == 0x80:
            raise SdoAbort(index, sub, struct.unpack_from("<I", resp, 4)[0])

    def upload(self, index, sub):
        head = struct.pack("<BHB", 0x40, index, sub)
        resp = self.sdo(head)
        self._check(resp, index, sub)
        assert resp[1:4] == head[1:4], resp.hex()
        if resp[0] & 0x02:  # expedited
            assert resp[0] & 0x01, resp.hex()
            return resp[4:8 - ((resp[0] >> 2) & 3)]
        assert resp[0] == 0x41, resp.hex()
        size = struct.unpack_from("<I", resp, 4)[0]
        data = b""
        toggle = 0
        while True:
            seg = self.sdo(bytes([0x60 | (toggle << 4)]))
            self._check(seg, index, sub)
            assert (seg[0] & 0xE0) == 0 and ((seg[0] >> 4) & 1) == toggle, seg.hex()
            data += seg[1:8 - ((seg[0] >> 1) & 7)]
            if seg[0] & 1:
                break
            toggle ^= 1
        assert len(data) == size, (len(data), size)
        return data

    def download(self, index, sub, data):
        data = bytes(data)
        if 1 <= len(data) <= 4:
            resp = self.sdo(struct.pack("<BHB", 0x23 | ((4 - len(data)) << 2), index, sub) + data)
            self._check(resp, index, sub)
            assert resp[:4] == struct.pack("<BHB", 0x60, index, sub), resp.hex()
            return
        resp = self.sdo(struct.pack("<BHBI", 0x21, index, sub, len(data)))
        self._check(resp, index, sub)
        toggle, pos = 0, 0
        while True:
            chunk = data[pos:pos + 7]
            pos += 7
            last = pos >= len(data)
            seg = self.sdo(bytes([(toggle << 4) | ((7 - len(chunk)) << 1) | (1 if last else 0)]) + chunk)
            self._check(seg, index, sub)
            assert seg[0] == 0x20 | (toggle << 4), seg.hex()
            if last:
                return
            toggle ^= 1

    def block_upload(self, index, sub, blksize=127, crc=True):
        resp = self.sdo(struct.pack("<BHBBB", 0xA4 if crc else 0xA0, index, sub, blksize, 0))
        self._check(resp, index, sub)
        assert resp[0] == (0xC6 if crc else 0xC2), resp.hex()
        size = struct.unpack_from("<I", resp, 4)[0]
        self.send(0x600 + self.node, bytes([0xA3]) + bytes(7))
        # one sub-block: every object of the shipped models fits into 127 segments
        data, seqs, last = b"", 0, False
        while not last:
            seg = self.recv_until(lambda m: m.arbitration_id == 0x580 + self.node)
            assert seg is not None, "block upload stalled"
            seqs += 1
            assert seg.data[0] & 0x7F == seqs and seqs <= blksize, bytes(seg.data).hex()
            data += bytes(seg.data[1:])
            last = bool(seg.data[0] & 0x80)
        end = self.sdo(bytes([0xA2, seqs, blksize]))
        self._check(end, index, sub)
        n = (end[0] >> 2) & 7
        assert end[0] & 0xE3 == 0xC1, end.hex()
        data = data[:len(data) - n]
        assert len(data) == size
        got_crc = struct.unpack_from("<H", end, 1)[0]
        assert got_crc == (crc16(data) if crc else 0), (hex(got_crc), hex(crc16(data)))
        self.send(0x600 + self.node, bytes([0xA1]) + bytes(7))
        return data

    def block_download(self, index, sub, data, crc=True):
        resp = self.sdo(struct.pack("<BHBI", 0xC6 if crc else 0xC2, index, sub, len(data)))
        self._check(resp, index, sub)
        assert resp[0] == (0xA4 if crc else 0xA0), resp.hex()
        blksize = resp[4]
        pos, seq = 0, 0
        while True:
            chunk = data[pos:pos + 7]
            pos += 7
            seq += 1
            last = pos >= len(data)
            frame = bytes([(0x80 if last else 0) | seq]) + chunk + bytes(7 - len(chunk))
            if last or seq == blksize:
                ack = self.sdo(frame)
                self._check(ack, index, sub)
                assert ack[0] == 0xA2 and ack[1] == seq, ack.hex()
                blksize, seq = ack[2], 0
                if last:
                    break
            else:
                self.send(0x600 + self.node, frame)
        n = (7 - len(data) % 7) % 7 if data else 7
        c = crc16(data) if crc else 0
        resp = self.sdo(struct.pack("<BH", 0xC1 | (n << 2), c) + bytes(5))
        self._check(resp, index, sub)
        assert resp[0] == 0xA1, resp.hex()

    # --- NMT ---------------------------------------------------------------------------------
    def nmt(self, command, node=None):
        self.send(0x000, bytes([command, self.node if node is None else node]))


class Raw:
    """A raw TCP connection to the SLCAN port, for byte-exact checks."""

    def __init__(self, port):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.buf = b""

    def close(self):
        self.sock.close()

    def send(self, data):
        self.sock.sendall(data)

    def read_until(self, predicate, timeout=2.0):
        """Reads until predicate(buffer) is true; returns the whole buffer and clears it."""
        deadline = time.monotonic() + timeout
        while not predicate(self.buf):
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"got {self.buf!r}")
            self.sock.settimeout(left)
            try:
                chunk = self.sock.recv(4096)
            except socket.timeout:
                continue
            if not chunk:
                break
            self.buf += chunk
        out, self.buf = self.buf, b""
        return out

    def exchange(self, data, expected, timeout=2.0):
        self.send(data)
        return self.read_until(lambda b: len(b) >= len(expected), timeout)
