"""A small FAULHABER MC V3.0 binary-protocol client for the integration tests (faulhaber.md §3–§6).

Written for mcemu's tests (not derived from any vendor or third-party code). It talks over any
pyserial port object: `serial.Serial(pty_path)` for `--faulhaber-pty`, or
`serial.serial_for_url("socket://127.0.0.1:PORT")` for `--faulhaber-port` — see `open_tcp` and
`open_pty`.

Two ways of waiting for an answer:
  - `Client.request()` (the default, careful): reads frames until one answers the request (same
    command, or an SDO error for an SDO request); asynchronous frames met on the way (boot 0x00,
    statusword 0x05, EMCY 0x07) are kept in `Client.notifications` in arrival order;
  - `Client.simple_request()` (the pattern of the public `mc5005.py` client, faulhaber.md §11.1):
    flush the input, send, take the FIRST frame that arrives as the answer — 2 bytes, then L more,
    CRC over bytes 1 … −2, value from byte 7. An asynchronous frame that arrives before the answer
    is taken for it; that is the point of running it with asynchronous messages on and off.
"""
import struct
import time

import serial

SOF = 0x53
EOF = 0x45

# command codes (faulhaber.md §5)
BOOT = 0x00
SDO_READ = 0x01
SDO_WRITE = 0x02
SDO_ERROR = 0x03
CONTROLWORD = 0x04
STATUSWORD = 0x05
LOGGING = 0x06
EMCY = 0x07
ASYNC_COMMANDS = (BOOT, STATUSWORD, EMCY)


def crc8(data):
    """CRC-8 of faulhaber.md §3: init 0xFF, reflected polynomial 0xD5, no final XOR."""
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xD5 if crc & 1 else crc >> 1
    return crc


def frame(node, command, data=b""):
    """The complete frame `S L node cmd data CRC E` (L = len(data) + 4)."""
    body = bytes([len(data) + 4, node & 0xFF, command & 0xFF]) + bytes(data)
    return bytes([SOF]) + body + bytes([crc8(body), EOF])


def sdo_read_frame(node, index, sub):
    return frame(node, SDO_READ, struct.pack("<HB", index, sub))


def sdo_write_frame(node, index, sub, value, size):
    if isinstance(value, (bytes, bytearray)):
        raw = bytes(value)
    else:
        raw = (value & ((1 << (8 * size)) - 1)).to_bytes(size, "little")
    return frame(node, SDO_WRITE, struct.pack("<HB", index, sub) + raw)


def controlword_frame(node, cw):
    return frame(node, CONTROLWORD, struct.pack("<H", cw & 0xFFFF))


class Frame:
    """One decoded frame."""

    def __init__(self, raw):
        self.raw = bytes(raw)
        self.length = raw[1]
        self.node = raw[2]
        self.command = raw[3]
        self.data = bytes(raw[4:-2])

    def __repr__(self):
        return f"Frame(node={self.node}, cmd=0x{self.command:02X}, data={self.data.hex(' ')})"

    # --- the drive's messages, decoded ---------------------------------------------------------
    @property
    def index(self):
        return struct.unpack_from("<H", self.data, 0)[0]

    @property
    def sub(self):
        return self.data[2]

    @property
    def value(self):
        """An SDO read answer's value bytes."""
        return self.data[3:]

    @property
    def abort_code(self):
        return struct.unpack_from("<I", self.data, 3)[0]

    @property
    def statusword(self):
        return struct.unpack_from("<H", self.data, 0)[0]

    @property
    def emcy(self):
        """(error code, error register 1001h, FAULHABER error word 2320h)."""
        code, register, word = struct.unpack_from("<HBH", self.data, 0)
        return code, register, word


class FrameParser:
    """Splits a byte stream into frames (the drive always sends correct frames; anything else is a
    test failure, so this parser is strict: bytes outside a frame raise)."""

    def __init__(self):
        self.buf = bytearray()

    def feed(self, data):
        self.buf += data
        out = []
        while len(self.buf) >= 2:
            if self.buf[0] != SOF:
                raise AssertionError(f"byte 0x{self.buf[0]:02X} outside a frame: {bytes(self.buf).hex(' ')}")
            total = self.buf[1] + 2
            if len(self.buf) < total:
                break
            raw = bytes(self.buf[:total])
            del self.buf[:total]
            if raw[-1] != EOF:
                raise AssertionError(f"frame without E: {raw.hex(' ')}")
            if crc8(raw[1:-2]) != raw[-2]:
                raise AssertionError(f"frame with a wrong CRC: {raw.hex(' ')}")
            out.append(Frame(raw))
        return out


class SdoError(Exception):
    def __init__(self, index, sub, code):
        super().__init__(f"SDO error {index:04X}.{sub:02X}: 0x{code:08X}")
        self.index, self.sub, self.code = index, sub, code


class Client:
    """A host talking to one node over a pyserial port."""

    def __init__(self, port, node=1, timeout=5.0):
        self.port = port
        self.node = node
        self.timeout = timeout
        self.parser = FrameParser()
        self.notifications = []  # asynchronous frames (boot, statusword, EMCY) in arrival order
        self.port.timeout = 0.05

    def close(self):
        self.port.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # --- raw I/O -------------------------------------------------------------------------------
    def send(self, data):
        self.port.write(bytes(data))
        self.port.flush()

    def _read_exact(self, n, deadline):
        data = b""
        while len(data) < n:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            self.port.timeout = min(remaining, 0.5)
            data += self.port.read(n - len(data))
        return data

    def read_frame(self, timeout=None):
        """The next frame from the drive (None after `timeout` seconds without one). A frame that
        has begun is read to its end (up to 5 s more)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        head = self._read_exact(1, deadline)
        if not head:
            return None
        rest_deadline = time.monotonic() + 5.0
        head += self._read_exact(1, rest_deadline)
        if len(head) == 2:
            head += self._read_exact(head[1], rest_deadline)
        frames = self.parser.feed(head)
        if len(frames) != 1 or self.parser.buf:
            raise AssertionError(f"incomplete frame from the drive: {head.hex(' ')}")
        return frames[0]

    def drain(self, quiet=0.1):
        """Reads until nothing arrives for `quiet` seconds; asynchronous frames are recorded, the
        list of every frame read is returned."""
        got = []
        while True:
            f = self.read_frame(timeout=quiet)
            if f is None:
                return got
            got.append(f)
            if f.command in ASYNC_COMMANDS:
                self.notifications.append(f)

    def wait_notification(self, predicate, timeout=None, what="notification"):
        """Waits for an asynchronous frame satisfying predicate; earlier recorded ones count too
        (they are consumed up to and including the match)."""
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        while True:
            for i, f in enumerate(self.notifications):
                if predicate(f):
                    del self.notifications[:i + 1]
                    return f
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise TimeoutError(f"no {what}; notifications seen: {self.notifications!r}")
            f = self.read_frame(timeout=remaining)
            if f is not None:
                if f.command not in ASYNC_COMMANDS:
                    raise AssertionError(f"unexpected frame while waiting for a {what}: {f!r}")
                self.notifications.append(f)

    # --- careful requests ------------------------------------------------------------------------
    def request(self, command, data=b"", node=None, answers=None):
        """Sends one request and returns its answer frame (asynchronous frames before it are
        recorded). `answers`: the commands that count as the answer (default: `command`, and
        SDO_ERROR for every command but the controlword)."""
        node = self.node if node is None else node
        if answers is None:
            answers = (command,) if command == CONTROLWORD else (command, SDO_ERROR)
        self.send(frame(node, command, data))
        deadline = time.monotonic() + self.timeout
        while True:
            f = self.read_frame(timeout=max(0.0, deadline - time.monotonic()))
            if f is None:
                raise TimeoutError(f"no answer to command 0x{command:02X} {bytes(data).hex(' ')}")
            if f.command in answers:
                return f
            if f.command in ASYNC_COMMANDS:
                self.notifications.append(f)
                continue
            raise AssertionError(f"unexpected frame {f!r} for command 0x{command:02X}")

    def sdo_read(self, index, sub=0, node=None):
        """The value bytes of index.sub; raises SdoError on an error frame."""
        f = self.request(SDO_READ, struct.pack("<HB", index, sub), node=node)
        if f.command == SDO_ERROR:
            raise SdoError(f.index, f.sub, f.abort_code)
        if (f.index, f.sub) != (index, sub):
            raise AssertionError(f"answer for {f.index:04X}.{f.sub:02X}, asked {index:04X}.{sub:02X}")
        return f.value

    def read_int(self, index, sub=0, signed=True, node=None):
        return int.from_bytes(self.sdo_read(index, sub, node=node), "little", signed=signed)

    def read_string(self, index, sub=0, node=None):
        return self.sdo_read(index, sub, node=node).decode("ascii")

    def sdo_write(self, index, sub, value, size, node=None):
        raw = value if isinstance(value, (bytes, bytearray)) else (value & ((1 << (8 * size)) - 1)).to_bytes(
            size, "little")
        f = self.request(SDO_WRITE, struct.pack("<HB", index, sub) + bytes(raw), node=node)
        if f.command == SDO_ERROR:
            raise SdoError(f.index, f.sub, f.abort_code)
        if (f.index, f.sub) != (index, sub) or len(f.data) != 3:
            raise AssertionError(f"bad write response {f!r}")

    def controlword(self, cw, node=None):
        """Command 0x04; returns the error byte (0 = OK)."""
        f = self.request(CONTROLWORD, struct.pack("<H", cw), node=node)
        if len(f.data) != 1:
            raise AssertionError(f"bad controlword response {f!r}")
        return f.data[0]

    def statusword(self):
        return self.read_int(0x6041, 0, signed=False)

    def position(self):
        return self.read_int(0x6064, 0)

    # --- the mc5005.py pattern ---------------------------------------------------------------------
    def simple_request(self, frame_bytes):
        """Flush input, send, the first frame that comes is the answer: read 2 bytes, then L more,
        check the CRC over bytes 1 … −2, return bytes 7 … −2 (the value of an SDO read answer)."""
        self.parser = FrameParser()
        self.port.reset_input_buffer()
        self.send(frame_bytes)
        self.port.timeout = self.timeout
        head = self.port.read(2)
        if len(head) != 2:
            raise TimeoutError(f"no answer to {frame_bytes.hex(' ')}")
        rest = self.port.read(head[1])
        whole = head + rest
        if len(whole) != head[1] + 2:
            raise TimeoutError(f"short answer {whole.hex(' ')} to {frame_bytes.hex(' ')}")
        if crc8(whole[1:-2]) != whole[-2]:
            raise AssertionError(f"CRC of {whole.hex(' ')}")
        self.last_simple_answer = whole
        return whole[7:-2]

    def simple_read(self, index, sub=0, signed=True):
        return int.from_bytes(self.simple_request(sdo_read_frame(self.node, index, sub)), "little", signed=signed)

    def simple_write(self, index, sub, value, size):
        self.simple_request(sdo_write_frame(self.node, index, sub, value, size))


def open_tcp(port, node=1, timeout=5.0, host="127.0.0.1"):
    return Client(serial.serial_for_url(f"socket://{host}:{port}", timeout=0.05), node=node, timeout=timeout)


def open_pty(path, node=1, timeout=5.0):
    # the baud rate is ignored by mcemu (faulhaber.md §2.2); 115200 as a real MC 5005 is usually set
    return Client(serial.Serial(path, 115200, timeout=0.05), node=node, timeout=timeout)
