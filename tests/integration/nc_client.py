"""netcat (Debian's netcat-openbsd) as the RefGo / UDP client of the integration tests.

`Nc` runs one `nc` process: the test writes request bytes to its stdin and reads what mcemu sent
from its stdout, as a Docklight or shell user would. `nc_once` is the shell idiom
`printf '...' | nc -N host port`. Every wait is bounded and polls; nothing sleeps a fixed time.
"""
import re
import shutil
import subprocess
import threading
import time

NC = shutil.which("nc") or "/usr/bin/nc"
TP = re.compile(rb"-?[0-9]+")


class Nc:
    """One nc process connected to 127.0.0.1:port (TCP, or UDP with udp=True)."""

    def __init__(self, port, udp=False, half_close=True, source_port=None):
        cmd = [NC]
        if udp:
            cmd.append("-u")
        elif half_close:
            cmd.append("-N")  # FIN towards mcemu when stdin closes (refgo.md §18)
        if source_port is not None:
            cmd += ["-p", str(source_port)]
        cmd += ["127.0.0.1", str(port)]
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                                     bufsize=0)
        self._buf = bytearray()
        self._cond = threading.Condition()
        self._eof = False
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        while True:
            chunk = self.proc.stdout.read1(65536) if hasattr(self.proc.stdout, "read1") else self.proc.stdout.read(1)
            with self._cond:
                if not chunk:
                    self._eof = True
                    self._cond.notify_all()
                    return
                self._buf += chunk
                self._cond.notify_all()

    def send(self, data):
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def wait(self, predicate, timeout=5.0, what="reply"):
        """Waits until predicate(buffer bytes) is true; returns the buffer (not consumed)."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while not predicate(bytes(self._buf)):
                left = deadline - time.monotonic()
                if left <= 0 or (self._eof and not predicate(bytes(self._buf))):
                    raise TimeoutError(f"nc: no {what} within {timeout} s; got {bytes(self._buf)!r}")
                self._cond.wait(min(left, 0.05))
            return bytes(self._buf)

    def take(self, n):
        with self._cond:
            out = bytes(self._buf[:n])
            del self._buf[:n]
            return out

    def take_all(self):
        with self._cond:
            out = bytes(self._buf)
            self._buf.clear()
            return out

    def replies(self, count, timeout=5.0):
        """Waits for `count` complete RefGo replies (each ends in '>' after CRLF, or is '>' alone)
        and returns them as a list. Works because no request in these tests contains '>'."""
        def split(buf):
            out = []
            start = 0
            for i, b in enumerate(buf):
                if b == ord(">"):
                    out.append(buf[start:i + 1])
                    start = i + 1
            return out

        self.wait(lambda b: len(split(b)) >= count, timeout, f"{count} replies")
        got = split(self.take_all())
        return got

    def request(self, line, timeout=5.0):
        """Sends one line with CR and returns its complete reply."""
        self.send(line.encode("latin-1") + b"\r")
        return self.replies(1, timeout)[0]

    def close_input(self):
        try:
            self.proc.stdin.close()
        except BrokenPipeError:
            pass

    def wait_exit(self, timeout=5.0):
        return self.proc.wait(timeout=timeout)

    def eof(self):
        with self._cond:
            return self._eof

    def close(self):
        self.close_input()
        try:
            self.proc.wait(timeout=2)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self._reader.join(timeout=2)
        self.proc.stdout.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def nc_once(port, data, timeout=5.0):
    """`printf data | nc -N 127.0.0.1 port`: returns (stdout bytes, seconds until nc exited)."""
    t0 = time.monotonic()
    r = subprocess.run([NC, "-N", "127.0.0.1", str(port)], input=data, stdout=subprocess.PIPE,
                       stderr=subprocess.DEVNULL, timeout=timeout)
    return r.stdout, time.monotonic() - t0


def vector_regex(expected):
    """A refgo.md §14 vector as a compiled regex of bytes: {TP} = a signed decimal. Anchored at both
    ends (as matches_vector() of the C++ tests, std::regex_match), so that assertRegex, which
    searches, cannot accept extra bytes before the reply (b"XYZ\\r\\n?\\r\\n>" is not b">")."""
    parts = expected.split(b"{TP}")
    return re.compile(b"\\A" + b"-?[0-9]+".join(re.escape(p) for p in parts) + b"\\Z", re.S)
