"""A RefGo client (TCP 10001 on a real drive; refgo.md): one line per request, one reply per line.

A reply is ``<echo>\\r\\n[<answer>\\r\\n]>``, or ``>`` alone for an empty line, an unknown command
word or an over-long line. A failed command answers ``<prefix>,ERROR,<abort code>h``; the typed
methods turn that into :class:`RefGoError`.
"""
from __future__ import annotations

import socket
import time
from dataclasses import dataclass


class RefGoError(Exception):
    """A RefGo command answered ``…,ERROR,<code>h`` (or had no answer where one was expected)."""

    def __init__(self, line: str, reply: "RefGoReply", message: str | None = None) -> None:
        self.line, self.reply = line, reply
        self.abort_code = reply.abort_code
        if message is None:
            message = f"{line!r} failed: {reply.answer!r}"
        super().__init__(message)


@dataclass(frozen=True)
class RefGoReply:
    raw: bytes
    echo: str | None
    answer: str | None

    @property
    def ok(self) -> bool:
        """False if the answer line reports an error (contains ``,ERROR,``)."""
        return self.answer is None or ",ERROR," not in self.answer

    @property
    def abort_code(self) -> int | None:
        """The abort code of an error answer (``OW6041,0,5,ERROR,06010002h`` → 0x06010002)."""
        if self.answer is None or ",ERROR," not in self.answer:
            return None
        return int(self.answer.rsplit(",ERROR,", 1)[1].rstrip("hH"), 16)


def _hex(n: int) -> str:
    return f"{n:X}"


class RefGo:
    """One RefGo TCP connection. ``exchange`` sends one line and returns the parsed reply; the
    other methods are typed shortcuts for the commands tests use most."""

    def __init__(self, host: str, port: int, timeout: float = 5.0) -> None:
        self.timeout = timeout
        self.sock = socket.create_connection((host, port), timeout=timeout)
        self._buf = bytearray()

    # --- transport ----------------------------------------------------------------------------
    def _fill(self, deadline: float) -> None:
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError(f"RefGo: no complete reply within {self.timeout} s; got {bytes(self._buf)!r}")
        self.sock.settimeout(left)
        chunk = self.sock.recv(4096)
        if not chunk:
            raise ConnectionError(f"RefGo: connection closed by the drive; got {bytes(self._buf)!r}")
        self._buf += chunk

    def _line(self, deadline: float) -> bytes:
        while (end := self._buf.find(b"\r\n")) < 0:
            self._fill(deadline)
        out = bytes(self._buf[:end])
        del self._buf[:end + 2]
        return out

    def _byte(self, deadline: float) -> int:
        while not self._buf:
            self._fill(deadline)
        return self._buf[0]

    def _read_reply(self) -> RefGoReply:
        deadline = time.monotonic() + self.timeout
        if self._byte(deadline) == ord(">"):  # empty, unknown or over-long line: '>' only
            del self._buf[:1]
            return RefGoReply(b">", None, None)
        echo = self._line(deadline)
        if self._byte(deadline) == ord(">"):
            del self._buf[:1]
            return RefGoReply(echo + b"\r\n>", echo.decode("latin-1"), None)
        answer = self._line(deadline)
        if self._byte(deadline) != ord(">"):
            raise ConnectionError(f"RefGo: expected '>' after the answer; got {bytes(self._buf)!r}")
        del self._buf[:1]
        return RefGoReply(echo + b"\r\n" + answer + b"\r\n>", echo.decode("latin-1"), answer.decode("latin-1"))

    def exchange(self, line: str) -> RefGoReply:
        """Sends ``line`` + CR and returns its reply."""
        if "\r" in line or "\n" in line:
            raise ValueError("one RefGo line, without CR or LF")
        self.sock.sendall(line.encode("latin-1") + b"\r")
        return self._read_reply()

    def command(self, line: str) -> str | None:
        """Sends a command and returns its answer line (None if it has none); raises
        :class:`RefGoError` on an error answer."""
        reply = self.exchange(line)
        if not reply.ok:
            raise RefGoError(line, reply)
        return reply.answer

    def _answer(self, line: str) -> str:
        reply = self.exchange(line)
        if not reply.ok or reply.answer is None:
            raise RefGoError(line, reply, None if reply.answer is not None else f"{line!r}: no answer line")
        return reply.answer

    # --- typed commands -------------------------------------------------------------------------
    def tp(self) -> int:
        """Actual position 6064h in user units."""
        return int(self._answer("TP"))

    def ts(self) -> int:
        """Simple status: 0 power off, 1 powered and idle, 2 moving, 9 fault."""
        return int(self._answer("TS"))

    def tpsr(self) -> int:
        """Process status register (8 hex digits)."""
        return int(self._answer("TPSR"), 16)

    def or_(self, index: int, sub: int, hex: bool = False) -> int | str:
        """Reads an object: an int for numeric entries, the text for string entries (1008h…).
        With ``hex=True`` the drive answers the 32-bit pattern in hex (returned as an unsigned int)."""
        prefix = f"OR{_hex(index)},{_hex(sub)}"
        answer = self._answer(prefix + (",h" if hex else ""))
        if not answer.upper().startswith(prefix + ","):
            raise RefGoError(prefix, RefGoReply(b"", None, answer), f"{prefix}: unexpected answer {answer!r}")
        value = answer[len(prefix) + 1:]
        try:
            return int(value[:-1], 16) if hex and value.endswith("h") else int(value)
        except ValueError:
            return value

    def ow(self, index: int, sub: int, value: int) -> None:
        """Writes an object; raises :class:`RefGoError` with the abort code if the drive refuses."""
        line = f"OW{_hex(index)},{_hex(sub)},{int(value)}"
        answer = self._answer(line)
        if not answer.endswith(",OK"):
            raise RefGoError(line, RefGoReply(b"", None, answer))

    def go(self, target: int | None = None) -> None:
        """``G<target>``: absolute move in profile position mode (switches the drive on if needed);
        ``go()`` without a target moves to the target set with ``PO``."""
        self.command("G" if target is None else f"G{int(target)}")

    def wait_idle(self, timeout: float = 10.0, interval: float = 0.005) -> None:
        """Polls ``TS`` until the drive is powered and not moving (1); a fault (9) or power off (0)
        raises :class:`RefGoError`."""
        deadline = time.monotonic() + timeout
        while (ts := self.ts()) == 2:
            if time.monotonic() >= deadline:
                raise TimeoutError(f"RefGo: still moving after {timeout} s (TP {self.tp()})")
            time.sleep(interval)
        if ts != 1:
            raise RefGoError("TS", RefGoReply(b"", "TS", str(ts)), f"TS = {ts}: the drive is "
                             + ("in fault" if ts == 9 else "not powered"))

    def close(self) -> None:
        self.sock.close()

    def __enter__(self) -> "RefGo":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
