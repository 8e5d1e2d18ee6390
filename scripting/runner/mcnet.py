# _mcemu_mcnet: the script's own TCP/UDP sockets (scripting.md §7). mcemu makes each socket in its
# own network namespace (bound to the drive's address, or connecting) and hands it over with the
# reply to an 'N' request: the sandboxed script process has no network and may not create sockets.
# The process holds the only copy, so the kernel closes them when it is killed. The single-threaded
# runner serves them (accept, connection retries, pending writes, receive buffers) whenever the
# script calls a module function or waits: Service is the hook the channel calls for that.
import errno
import os
import select
import socket
import time

MAX_OBJECTS = 8
RX_BUFFER = 4096
RETRY_S = 1.0  # TCP client reconnect interval, wall time (a socket-level timeout)

_KIND_SERVER, _KIND_CLIENT, _KIND_UDP = 'server', 'client', 'udp'


def _check_kw(kw):
    if kw:
        raise TypeError('function does not take keyword arguments')


def _decode(data):
    try:
        return data.decode('utf-8')
    except UnicodeDecodeError:
        return data.decode('latin-1')


def parse_settings(text):
    """(kind, host, port) or None for a malformed settings string (scripting.md §7.2)."""
    if not isinstance(text, str):
        return None
    parts = text.split(':')

    def port_of(p):
        if not p.isdigit():
            return None
        n = int(p)
        return n if 1 <= n <= 65535 else None

    head = parts[0].upper()
    if head == 'SERVER' and len(parts) in (2, 3):
        port = port_of(parts[-1])
        return None if port is None else (_KIND_SERVER, None, port)
    if head == 'UDP' and len(parts) == 2:
        port = port_of(parts[1])
        return None if port is None else (_KIND_UDP, None, port)
    if head == 'UDP' and len(parts) == 3 and parts[1]:
        port = port_of(parts[2])
        return None if port is None else (_KIND_UDP, parts[1], port)
    if len(parts) == 2 and parts[0]:
        port = port_of(parts[1])
        return None if port is None else (_KIND_CLIENT, parts[0], port)
    return None


class Service:
    """The channel's view of every open McNet object."""

    def __init__(self, log):
        self.objects = []
        self.log = log

    def active(self):
        return bool(self.objects)

    def fds(self):
        rd, wr = [], []
        for o in self.objects:
            o._fds(rd, wr)
        return rd, wr

    def timeout(self, reconnect=True):
        due = [o._retry_at for o in self.objects if o._retry_at is not None] if reconnect else []
        if not due:
            return None
        return max(0.0, min(due) - time.monotonic())

    def poll(self, readable, writable, reconnect=True):
        for o in list(self.objects):
            o._serve(readable, writable, reconnect)

    def poll_now(self):
        rd, wr = self.fds()
        try:
            r, w, _ = select.select(rd, wr, [], 0) if (rd or wr) else ([], [], [])
        except (OSError, ValueError):
            r, w = [], []
        self.poll(r, w)


def _opened(answer):
    """(socket, peer) of a net_open answer; OSError(errno) when mcemu could not make it."""
    err, sock, peer = answer
    if sock is None:
        raise OSError(err, os.strerror(err))
    return sock, peer


class LineMode:
    def __init__(self):
        self.text = False
        self.start = 0
        self.end = 10
        self.min_len = 0
        self.max_len = 0
        self.timeout_ms = 0


def make_class(service, channel, bind_address):
    """The McNet class of the script's `mcnet` module. (bind_address: the drive's --bind, where
    mcemu binds the sockets; only for the reader, the runner never binds.)"""

    class McNet:
        def __init__(self, *args, **kw):
            _check_kw(kw)
            if len(args) != 1:
                raise TypeError('function takes 2 positional arguments but %d were given' % (len(args) + 1))
            self._sock = None
            self._listen = None
            self._kind = None
            self._peer = None
            self._last_sender = None
            self._retry_at = None
            self._connected = False
            self._rx = bytearray()
            self._tx = bytearray()
            self._mode = LineMode()
            self._open = False
            if len(service.objects) >= MAX_OBJECTS:
                raise OSError(errno.ENFILE)
            err = self._do_open(args[0])
            if err:
                raise OSError(err)

        # ---- opening and closing
        def _do_open(self, settings):
            parsed = parse_settings(settings)
            if parsed is None:
                return errno.EINVAL
            if len(service.objects) >= MAX_OBJECTS and self not in service.objects:
                return errno.ENFILE
            kind, host, port = parsed
            self._kind, self._rx, self._tx = kind, bytearray(), bytearray()
            self._connected, self._last_sender, self._retry_at = False, None, None
            try:
                if kind == _KIND_SERVER:
                    self._listen = _opened(channel.net_open('server', '', port))[0]
                elif kind == _KIND_UDP:
                    self._sock, peer = _opened(channel.net_open('udp', host, port))
                    self._peer = (peer or host, port) if host else None
                else:
                    self._peer = (host, port)
                    self._connect()
            except OSError as e:
                self._close_sockets()
                if kind != _KIND_CLIENT:
                    service.log('mcnet: cannot bind %s port %d: %s' % (kind, port, e.strerror or e))
                return e.errno or errno.EIO
            self._open = True
            if self not in service.objects:
                service.objects.append(self)
            return 0

        def _connect(self):
            self._retry_at = None
            try:
                err, self._sock, _ = channel.net_open('client', self._peer[0], self._peer[1])
            except OSError as e:
                err, self._sock = e.errno or errno.EIO, None
            if self._sock is None:  # refused, unresolvable host name…: keep retrying
                self._drop_client()
            elif err == 0:
                self._connected = True

        def _drop_client(self):
            if self._sock is not None:
                self._sock.close()
            self._sock = None
            self._connected = False
            self._tx = bytearray()
            if self._kind == _KIND_CLIENT:
                self._retry_at = time.monotonic() + RETRY_S

        def _close_sockets(self):
            for s in (self._sock, self._listen):
                if s is not None:
                    s.close()
            self._sock = self._listen = None
            self._connected = False

        def open(self, *args, **kw):
            _check_kw(kw)
            if len(args) != 1:
                raise TypeError('function takes 2 positional arguments but %d were given' % (len(args) + 1))
            self._close_sockets()
            if self in service.objects:
                service.objects.remove(self)
            self._open = False
            return self._do_open(args[0]) == 0

        def close(self, *args, **kw):
            _check_kw(kw)
            self._close_sockets()
            self._open = False
            self._retry_at = None
            if self in service.objects:
                service.objects.remove(self)

        def is_open(self, *args, **kw):
            _check_kw(kw)
            return self._open

        def is_connected(self, *args, **kw):
            _check_kw(kw)
            service.poll_now()
            if not self._open:
                return False
            return True if self._kind == _KIND_UDP else self._connected

        # ---- serving (called by Service)
        def _fds(self, rd, wr):
            if self._listen is not None and self._sock is None:
                rd.append(self._listen)
            if self._sock is not None:
                if self._kind == _KIND_CLIENT and not self._connected:
                    wr.append(self._sock)
                else:
                    if len(self._rx) < RX_BUFFER:
                        rd.append(self._sock)
                    if self._tx:
                        wr.append(self._sock)

        def _serve(self, readable, writable, reconnect=True):
            if self._kind == _KIND_SERVER:
                if self._sock is None and self._listen is not None:
                    try:
                        c, _ = self._listen.accept()
                        c.setblocking(False)
                        self._sock, self._connected = c, True
                    except (BlockingIOError, InterruptedError):
                        pass
                    except OSError:
                        pass
            elif self._kind == _KIND_CLIENT:
                if self._sock is None:
                    if reconnect and self._retry_at is not None and time.monotonic() >= self._retry_at:
                        self._connect()
                    return
                if not self._connected:
                    if self._sock in writable:
                        err = self._sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR)
                        if err == 0:
                            self._connected = True
                        else:
                            self._drop_client()
                    return
            if self._sock is None:
                return
            if self._kind == _KIND_UDP:
                while True:
                    try:
                        data, sender = self._sock.recvfrom(65536)
                    except (BlockingIOError, InterruptedError):
                        break
                    except OSError:
                        break
                    self._last_sender = sender
                    if len(self._rx) + len(data) <= RX_BUFFER:
                        self._rx += data
                return
            self._pump_stream()

        def _pump_stream(self):
            while len(self._rx) < RX_BUFFER:
                try:
                    data = self._sock.recv(RX_BUFFER - len(self._rx))
                except (BlockingIOError, InterruptedError):
                    break
                except OSError:
                    data = b''
                if not data:
                    self._drop_client()
                    return
                self._rx += data
            while self._tx:
                try:
                    n = self._sock.send(self._tx)
                except (BlockingIOError, InterruptedError):
                    break
                except OSError:
                    self._drop_client()
                    return
                del self._tx[:n]

        # ---- data
        def write(self, *args, **kw):
            _check_kw(kw)
            if len(args) != 1:
                raise TypeError('function takes 2 positional arguments but %d were given' % (len(args) + 1))
            data = args[0]
            data = data.encode('utf-8') if isinstance(data, str) else bytes(data)
            service.poll_now()
            if not self._open:
                return -1
            if self._kind == _KIND_UDP:
                to = self._peer or self._last_sender
                if to is None:
                    return -1
                try:
                    return self._sock.sendto(data, to)
                except OSError:
                    return -1
            if not self._connected or self._sock is None:
                return -1
            self._tx += data
            self._pump_stream()
            return len(data)

        def _result(self, data):
            data = bytes(data)
            return _decode(data) if self._mode.text else data

        def in_waiting(self, *args, **kw):
            _check_kw(kw)
            service.poll_now()
            return len(self._rx) if self._open else -1

        def reset_input_buffer(self, *args, **kw):
            _check_kw(kw)
            service.poll_now()
            self._rx = bytearray()

        def read(self, *args, **kw):
            _check_kw(kw)
            size = int(args[0]) if args else 0
            service.poll_now()
            if not self._open or not self._rx:
                return None
            n = len(self._rx) if size <= 0 else min(size, len(self._rx))
            out = self._rx[:n]
            del self._rx[:n]
            return self._result(out)

        def read_until(self, *args, **kw):
            _check_kw(kw)
            expected = args[0] if args else '\n'
            size = int(args[1]) if len(args) > 1 else 0
            expected = expected.encode('utf-8') if isinstance(expected, str) else bytes(expected)
            service.poll_now()
            if not self._open or not self._rx:
                return None
            at = self._rx.find(expected) if expected else -1
            n = len(self._rx) if at < 0 else at + len(expected)
            if size > 0:
                n = min(n, size)
            out = self._rx[:n]
            del self._rx[:n]
            return self._result(out)

        def set_line_mode(self, *args, **kw):
            _check_kw(kw)
            if len(args) != 6:
                raise TypeError('function takes 7 positional arguments but %d were given' % (len(args) + 1))
            text_mode, start, end, min_len, max_len, timeout = [int(a) for a in args]
            if timeout > 60000 or not 0 <= start <= 255 or not 0 <= end <= 255:
                return -1
            m = LineMode()
            m.text, m.start, m.end = text_mode > 0, start, end
            m.min_len, m.max_len, m.timeout_ms = max(0, min_len), max(0, max_len), max(0, timeout)
            self._mode = m
            return 0

        def _frame(self):
            """Extracts one frame per the line mode, or returns None."""
            m, rx = self._mode, self._rx
            while True:
                if m.start:
                    at = rx.find(bytes([m.start]))
                    if at < 0:
                        del rx[:]
                        return None
                    del rx[:at]
                if not rx:
                    return None
                if not m.end:
                    need = m.max_len or m.min_len or len(rx)
                    if len(rx) < need:
                        return None
                    out = rx[:need]
                    del rx[:need]
                    return out
                limit = len(rx) if not m.max_len else min(len(rx), m.max_len)
                pos = max(0, m.min_len - 1)
                while pos < limit:
                    if rx[pos] == m.end:
                        out = rx[:pos + 1]
                        del rx[:pos + 1]
                        return out
                    pos += 1
                if m.max_len and len(rx) >= m.max_len:
                    del rx[:1]  # no end marker within max_len: resynchronise (scripting.md §7.4)
                    continue
                return None

        def readline(self, *args, **kw):
            _check_kw(kw)
            service.poll_now()
            if not self._open:
                return None
            frame = self._frame()
            if frame is None and self._mode.timeout_ms > 0:
                holder = []

                def arrived():
                    if not holder:
                        f = self._frame()
                        if f is not None:
                            holder.append(f)
                    return bool(holder)

                channel.sleep_us(self._mode.timeout_ms * 1000, arrived)
                frame = holder[0] if holder else self._frame()
            return None if frame is None else self._result(frame)

    McNet.__module__ = 'mcnet'
    return McNet
