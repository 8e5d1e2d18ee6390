"""A listener of the drive's UDP debug console (UDP 14999 on a real drive; udp-debug.md).

``register()`` sends one CR from the listener's own socket; the drive answers with its backlog
(the start-up lines after power-up), the CR echoed and the prompt ``>\\r\\n``, and from then on
sends every console message to that socket. Messages end in ``\\r\\n`` or ``\\n\\r`` (both are
line ends here).
"""
from __future__ import annotations

import re
import socket
import threading
import time

_LINE_END = re.compile(rb"\r\n|\n\r|\r|\n")


class UdpConsole:
    """One UDP socket that registers with a drive and collects what it sends."""

    def __init__(self, host: str, port: int, timeout: float = 5.0, bind: str | None = None) -> None:
        self.drive = (host, port)
        self.timeout = timeout
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind((bind or ("127.0.0.1" if host.startswith("127.") else "0.0.0.0"), 0))
        self.sock.settimeout(0.1)
        self._data = bytearray()
        self._datagrams: list[bytes] = []
        self._cond = threading.Condition()
        self._closed = False
        self._thread = threading.Thread(target=self._receive, name="mcemu-udp", daemon=True)
        self._thread.start()

    def _receive(self) -> None:
        while not self._closed:
            try:
                data, source = self.sock.recvfrom(65536)
            except socket.timeout:
                continue
            except OSError:
                return
            if source != self.drive:
                continue
            with self._cond:
                self._datagrams.append(data)
                self._data += data
                self._cond.notify_all()

    def _wait(self, predicate, timeout: float | None, what: str):
        deadline = time.monotonic() + (self.timeout if timeout is None else timeout)
        with self._cond:
            while not (result := predicate()):
                left = deadline - time.monotonic()
                if left <= 0:
                    raise TimeoutError(f"UDP console: no {what}; received {bytes(self._data)!r}")
                self._cond.wait(left)
            return result

    def register(self, payload: bytes = b"\r", timeout: float | None = None) -> bytes:
        """Registers as a listener and returns the drive's initial answer: backlog, the echoed
        ``payload`` and the prompt (the backlog may arrive in several datagrams)."""
        with self._cond:
            start = len(self._data)
        self.sock.sendto(payload, self.drive)
        end = payload + b">\r\n"

        def answered():
            with_answer = self._data.find(end, start)
            return with_answer + len(end) if with_answer >= 0 else None

        stop = self._wait(answered, timeout, "answer to the registration")
        with self._cond:
            return bytes(self._data[start:stop])

    @property
    def data(self) -> bytes:
        """Everything received so far, as one byte string."""
        with self._cond:
            return bytes(self._data)

    @property
    def datagrams(self) -> list[bytes]:
        with self._cond:
            return list(self._datagrams)

    def lines(self) -> list[str]:
        """Every complete line received so far (without line ends; empty lines and the bare ``>``
        prompt left out)."""
        with self._cond:
            data = bytes(self._data)
        pieces = _LINE_END.split(data)
        if not data.endswith((b"\r", b"\n")):
            pieces = pieces[:-1]  # the last piece has no line end yet
        return [p.decode("latin-1") for p in pieces if p and p != b">"]

    def wait_line(self, pattern: str, timeout: float | None = None) -> str:
        """Waits for a line that matches the regex ``pattern`` and returns it."""
        rx = re.compile(pattern)
        return self._wait(lambda: next((line for line in self.lines() if rx.search(line)), None), timeout,
                          f"line matching {pattern!r}")

    def close(self) -> None:
        self._closed = True
        self.sock.close()
        self._thread.join(timeout=1)

    def __enter__(self) -> "UdpConsole":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
