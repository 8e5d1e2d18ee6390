# _mcemu_ipc: the runner's side of the socketpair to mcemu's loop and of the shared drive-time
# page (scripting.md §10.2). The message layout is scripting/core/ipc.hpp's:
#   frame := u32 LE payload length, payload;  payload := kind byte, body
#   values := u16 LE count, then per value 'N' | 'I' i64 | 'B' u32 len bytes | 'S' u32 len UTF-8
# Every call is synchronous: one request, then exactly one 'R' reply (or 'W' for a sleep). The one
# exception: during a sleep, mcnet may ask for a socket ('N', net_open) — its 'R' reply is told
# apart from the sleep's 'W', which is kept for the sleep. mcemu makes the socket (the sandboxed
# runner may not) and attaches it to that reply (SCM_RIGHTS).
import mmap
import os
import select
import socket
import struct
import time

FD_SOCKET = 4
FD_PAGE = 5

# Shared page layout (scripting/shared_page.hpp): the loop writes seq/time/mono/flags, the
# runner writes line/line_seq from its SIGUSR1 handler.
PAGE_SIZE = 4096
_TIME = struct.Struct('<IIQQI')  # seq, pad, time_ms, mono_ns at that step, flags
_SEQ = struct.Struct('<I')
OFF_LINE = 64
FLAG_INTERPOLATE = 1

_LEN = struct.Struct('<I')
_Q = struct.Struct('<q')
_U32 = struct.Struct('<I')
_U16 = struct.Struct('<H')
_REPLY_NONE = b'\x01\x00N'
_FDS_SPACE = socket.CMSG_SPACE(4 * 4)

TICKS_PERIOD = 1 << 30


def encode_values(values):
    out = [_U16.pack(len(values))]
    for v in values:
        if v is None:
            out.append(b'N')
        elif isinstance(v, int):
            out.append(b'I' + _Q.pack(v))
        elif isinstance(v, str):
            b = v.encode('utf-8', 'surrogateescape')
            out.append(b'S' + _U32.pack(len(b)) + b)
        else:
            b = bytes(v)
            out.append(b'B' + _U32.pack(len(b)) + b)
    return b''.join(out)


def decode_values(body):
    n = _U16.unpack_from(body, 0)[0]
    at = 2
    out = []
    for _ in range(n):
        tag = body[at]
        at += 1
        if tag == 78:  # N
            out.append(None)
        elif tag == 73:  # I
            out.append(_Q.unpack_from(body, at)[0])
            at += 8
        else:
            size = _U32.unpack_from(body, at)[0]
            at += 4
            raw = bytes(body[at:at + size])
            at += size
            out.append(raw.decode('utf-8', 'surrogateescape') if tag == 83 else raw)
    return out


class Closed(Exception):
    """mcemu closed the channel: the run is over."""


class Channel:
    def __init__(self, sock=None, page=None):
        self.sock = sock if sock is not None else socket.socket(fileno=FD_SOCKET)
        self.sock.setblocking(True)
        self.page = page if page is not None else mmap.mmap(FD_PAGE, PAGE_SIZE)
        self.buf = bytearray()
        self.service = None  # mcnet: object with fds(), timeout(), poll(readable, writable)
        self.line_seq = 0
        self._last_us = 0
        self._call_structs = {}
        self.sleeping = False  # inside sleep_us: mcnet may open sockets while it waits
        self._pending = []  # frames read by net_open that belong to the sleep

    # ---- sending
    def send(self, kind, body=b''):
        self.sock.sendall(_LEN.pack(len(body) + 1) + kind + body)

    def output(self, text):
        if isinstance(text, str):
            data = text.encode('utf-8', 'surrogateescape')
        else:
            data = bytes(text)
        # frames stay well below the loop's 1 MiB limit
        for i in range(0, len(data), 65536):
            self.send(b'O', data[i:i + 65536])

    # ---- receiving
    def recv_message(self, wakeup=None):
        """The next message as (kind, body). With `wakeup` (a predicate), returns (0, b'') as soon
        as it holds while waiting (mcnet readline: a frame arrived during its timeout)."""
        if self._pending:
            return self._pending.pop(0)
        buf = self.buf
        while True:
            if len(buf) >= 4:
                n = _LEN.unpack_from(buf, 0)[0]
                if len(buf) >= 4 + n:
                    kind = buf[4]
                    body = bytes(buf[5:4 + n])
                    del buf[:4 + n]
                    return kind, body
            svc = self.service
            if svc is not None and svc.active():
                # Serve the script's own sockets while the loop has not answered yet; a client
                # reconnects only during a sleep (a call's reply must be the next 'R').
                while True:
                    if wakeup is not None and wakeup():
                        return 0, b''
                    if self._pending:
                        return self._pending.pop(0)
                    rd, wr = svc.fds()
                    r, w, _ = select.select([self.sock] + rd, wr, [], svc.timeout(self.sleeping))
                    svc.poll(r, w, self.sleeping)
                    if self._pending:
                        return self._pending.pop(0)
                    if self.sock in r:
                        break
            data = self.sock.recv(65536)
            if not data:
                raise Closed()
            buf += data

    def reply(self):
        kind, body = self.recv_message()
        if kind != 82:  # R
            raise Closed()
        if body == _REPLY_NONE:
            return None
        values = decode_values(body)
        return values[0] if len(values) == 1 else values

    # ---- calls
    def call(self, function, args):
        svc = self.service
        if svc is not None and svc.active():
            svc.poll_now()
        if all(type(a) is int for a in args):
            st = self._call_structs.get(len(args))
            if st is None:
                st = struct.Struct('<IcHH' + 'cq' * len(args))
                self._call_structs[len(args)] = st
            flat = []
            for a in args:
                flat.append(b'I')
                flat.append(a)
            self.sock.sendall(st.pack(st.size - 4, b'C', function, len(args), *flat))
        else:
            self.send(b'C', _U16.pack(function) + encode_values(args))
        return self.reply()

    def net_open(self, kind, host, port):
        """A socket for mcnet, made by mcemu: (errno, socket or None, peer address text). errno 0
        or EINPROGRESS (a client still connecting) come with the socket."""
        self.send(b'N', encode_values([kind, host or '', int(port)]))
        fds = []
        buf = self.buf
        try:
            while True:
                if len(buf) >= 4:
                    n = _LEN.unpack_from(buf, 0)[0]
                    if len(buf) >= 4 + n:
                        kind_b, body = buf[4], bytes(buf[5:4 + n])
                        del buf[:4 + n]
                        if kind_b == 82:  # R: ours
                            break
                        self._pending.append((kind_b, body))  # the sleep's 'W'
                        continue
                data, anc, _, _ = self.sock.recvmsg(65536, _FDS_SPACE, socket.MSG_CMSG_CLOEXEC)
                for level, ctype, cdata in anc:
                    if level == socket.SOL_SOCKET and ctype == socket.SCM_RIGHTS:
                        usable = len(cdata) - len(cdata) % 4
                        fds.extend(struct.unpack('<%di' % (usable // 4), cdata[:usable]))
                if not data:
                    raise Closed()
                buf += data
        except BaseException:
            for fd in fds:
                os.close(fd)
            raise
        values = decode_values(body)
        err, peer = values[0], values[1]
        sock = None
        if fds:
            sock = socket.socket(fileno=fds[0])
            sock.setblocking(False)
            for fd in fds[1:]:
                os.close(fd)
        return err, sock, peer

    def sleep_us(self, us, wakeup=None):
        """Sleeps `us` µs of drive time (rounded up to whole steps by the loop). With `wakeup`, the
        sleep is cancelled as soon as the predicate holds (the loop then wakes it at once)."""
        if us <= 0:
            return
        self.send(b'Z', encode_values([int(us)]))
        self.sleeping = True
        try:
            while True:
                kind, body = self.recv_message(wakeup)
                if kind == 87:  # W
                    return
                if kind == 0:
                    wakeup = None
                    self.send(b'X')
                    continue
                raise Closed()
        finally:
            self.sleeping = False

    # ---- drive time from the shared page
    def _read_time(self):
        page = self.page
        while True:
            seq, _, t, mono, flags = _TIME.unpack_from(page, 0)
            if seq & 1:
                continue
            if _SEQ.unpack_from(page, 0)[0] == seq:
                return t, mono, flags

    def ticks_ms(self):
        return self._read_time()[0] % TICKS_PERIOD

    def now_ms(self):
        return self._read_time()[0]

    def ticks_us(self):
        t, mono, flags = self._read_time()
        us = t * 1000
        if flags & FLAG_INTERPOLATE and mono:
            extra = (time.monotonic_ns() - mono) // 1000
            us += 0 if extra < 0 else (999 if extra > 999 else extra)
        # a late or catch-up step must not make the value jump back (scripting.md §8.2)
        if us < self._last_us:
            us = self._last_us
        self._last_us = us
        return us % TICKS_PERIOD

    def set_line(self, line):
        self.line_seq = (self.line_seq + 1) & 0xFFFFFFFF
        struct.pack_into('<II', self.page, OFF_LINE, line & 0xFFFFFFFF, self.line_seq)


def exit_now(status=0):
    os._exit(status)
