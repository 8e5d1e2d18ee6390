"""Start the real mcemu binary for integration tests and talk to it.

The binary comes from $MCEMU_BIN (CTest sets it). Every service is started on port 0; the ports
are read from the start-up log ("listening: refgo tcp 127.0.0.1:43215"). Everything is bounded in
time and polls instead of sleeping for fixed periods.
"""
import json
import os
import re
import signal
import socket
import subprocess
import tempfile
import threading
import time
import urllib.error
import urllib.request

MCEMU = os.environ.get("MCEMU_BIN", os.path.join(os.path.dirname(__file__), "../../build/server/mcemu"))
LISTEN_RE = re.compile(r"(?:drive (\d+): )?listening: (\w+) (tcp|udp) ([^ ]+):(\d+)")
# What AddressSanitizer, LeakSanitizer and UndefinedBehaviorSanitizer print when the binary under
# test was built with them (tools/dev test runs the integration suite against such a build too).
# Set by tools/dev for the run against the ASan+UBSan build: memory figures (VmRSS) are not
# meaningful there (freed memory stays in ASan's quarantine).
SANITIZED = os.environ.get("MCEMU_SANITIZED") == "1"
SANITIZER_MARKERS = ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:", "WARNING: ThreadSanitizer")


def wait_for(predicate, timeout=10.0, interval=0.01, what="condition"):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(interval)
    raise TimeoutError(f"timed out waiting for {what}")


class Mcemu:
    """One running mcemu process. Use as a context manager."""

    def __init__(self, *args, state_dir=None, env=None, ports_zero=True, ready=True):
        self.tmp = None
        if state_dir is None:
            self.tmp = tempfile.TemporaryDirectory(prefix="mcemu-it-")
            state_dir = os.path.join(self.tmp.name, "state")
        self.state_dir = state_dir
        cmd = [MCEMU, "--state-dir", state_dir]
        if ports_zero:
            cmd += ["--refgo-port", "0", "--slcan-port", "0", "--http-port", "0", "--udp-port", "0",
                    "--faulhaber-port", "0"]
        cmd += list(args)
        full_env = dict(os.environ)
        full_env.update(env or {})
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     env=full_env, text=True)
        self.lines = []
        self.ports = {}  # service -> port of drive 1
        self.drives = {}  # drive number -> {service: (address, port)} (fleets: "drive k: listening: …")
        self._lock = threading.Lock()
        self._reader = threading.Thread(target=self._read_log, daemon=True)
        self._reader.start()
        if ready:
            try:
                wait_for(lambda: self.has_line("ready") or self.proc.poll() is not None, what="mcemu ready")
            except TimeoutError:
                self.kill()
                raise
            if self.proc.poll() is not None:
                raise RuntimeError("mcemu exited at start-up:\n" + self.log())

    def _read_log(self):
        for line in self.proc.stderr:
            with self._lock:
                self.lines.append(line.rstrip("\n"))
                m = LISTEN_RE.search(line)
                if m:
                    drive = int(m.group(1) or 1)
                    self.drives.setdefault(drive, {})[m.group(2)] = (m.group(4), int(m.group(5)))
                    if drive == 1:
                        self.ports[m.group(2)] = int(m.group(5))

    def log(self):
        with self._lock:
            return "\n".join(self.lines)

    def has_line(self, text):
        with self._lock:
            return any(text in l for l in self.lines)

    def count_lines(self, text):
        with self._lock:
            return sum(1 for l in self.lines if text in l)

    def wait_exit(self, timeout=10):
        try:
            rc = self.proc.wait(timeout=timeout)
        finally:
            self._reader.join(timeout=2)
            self.proc.stderr.close()
        return rc

    def terminate(self, sig=signal.SIGTERM, timeout=10):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        return self.wait_exit(timeout)

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
        return self.wait_exit()

    def __enter__(self):
        return self

    def sanitizer_report(self):
        """The sanitizer report lines in the log (empty for a clean run or a build without them)."""
        with self._lock:
            return [l for l in self.lines if any(marker in l for marker in SANITIZER_MARKERS)]

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.terminate()
        else:
            self.wait_exit()
        if self.tmp:
            self.tmp.cleanup()
        report = self.sanitizer_report()
        if report and exc[0] is None:
            raise AssertionError("mcemu reported a sanitizer finding:\n" + "\n".join(report) + "\n--- log:\n" +
                                 self.log()[-8000:])

    # --- HTTP JSON API -----------------------------------------------------------------------
    def http(self, method, path, body=None, content_type="application/json", timeout=10, drive=1):
        data = None if body is None else (body if isinstance(body, bytes) else json.dumps(body).encode())
        address, port = self.drives[drive]["http"]
        req = urllib.request.Request(f"http://{address}:{port}{path}", data=data, method=method)
        if data is not None and content_type:
            req.add_header("Content-Type", content_type)
        try:
            with urllib.request.urlopen(req, timeout=timeout) as resp:
                return resp.status, resp.read()
        except urllib.error.HTTPError as e:
            return e.code, e.read()

    def read_object(self, index, sub):
        status, body = self.http("GET", f"/api/v1/objects/{index:04X}/{sub:02X}h")
        if status != 200:
            raise AssertionError(f"read {index:04X}.{sub}: HTTP {status} {body!r}")
        return json.loads(body)["value"]

    def read_object_of(self, drive, index, sub):
        status, body = self.http("GET", f"/api/v1/objects/{index:04X}/{sub:02X}h", drive=drive)
        if status != 200:
            raise AssertionError(f"drive {drive}: read {index:04X}.{sub}: HTTP {status} {body!r}")
        return json.loads(body)["value"]

    def write_object(self, index, sub, value):
        status, body = self.http("PUT", f"/api/v1/objects/{index:04X}/{sub:02X}h", {"value": value})
        return status, json.loads(body)

    def store(self):
        return self.http("POST", "/api/v1/store", {})


def connect(port, timeout=5.0):
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    return s


def fill_trace_ring(port, lines=5000):
    """Fills the trace ring (10 000 events, web.md §8.6) with RefGo traffic: every line and reply is
    an event, so 5000 lines fill it. Memory tests take their baseline after this, so that what they
    measure is the structure under test, not the (bounded) ring filling up."""
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    try:
        s.sendall(b"TP\r" * lines)
        got = 0
        while got < lines:
            chunk = s.recv(65536)
            if not chunk:
                raise AssertionError("mcemu closed the connection while filling the trace ring")
            got += chunk.count(b">")
    finally:
        s.close()


def refgo_line(sock, line):
    """Sends one RefGo line (CR appended) on an open socket and returns the whole reply, up to and
    including the prompt `>`."""
    sock.sendall(line.encode() + b"\r")
    data = b""
    while not data.endswith(b">"):
        chunk = sock.recv(4096)
        if not chunk:
            raise ConnectionError("RefGo connection closed")
        data += chunk
    return data
