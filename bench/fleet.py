#!/usr/bin/python3
"""Fleet benchmark (issue 13): CPU and memory of one mcemu process with N drives, idle and moving
(every drive in RefGo Back & Forth), and the speed-up of --clock manual (drive time per wall time
of POST /api/v1/clock/advance with every drive moving). A benchmark: it prints, never asserts.

CPU % of one core = (utime + stime) ticks from /proc/<pid>/stat over WINDOW s / CLK_TCK; VmRSS and
VmHWM from /proc/<pid>/status at the end of the windows (KiB/drive = VmRSS / N, the process's own
~8 MiB included); start-up = wall time from exec to the "ready" log line. Each (N,
mode) is measured ROUNDS times, alternating, and the median printed.

usage: bench/fleet.py [BINARY] [N …]   env: WINDOW (10), ROUNDS (3), ADVANCE_MS (60000), MOVING_MAX (100)

Fleets above MOVING_MAX drives are measured idle only (default 100; issue 26 asks for the moving
numbers of 1000 drives: MOVING_MAX=1000). A fleet whose moving steps need more than the one core
of the event loop falls behind real time (logged), and its moving % then says "one core,
saturated"; the manual column (drive time per wall time while every drive moves) says how far.
The lag column is how far the drive time of the last drive fell behind the wall time over the
moving window (GET /api/v1/status timeMs before and after, less the wall time between; 0 or a few
ms: real time held; the two status requests themselves wait for the step in progress). The logged
column is the issue's own criterion ("no lag logged"): how many "simulation is N ms behind real
time" lines mcemu wrote during the moving windows, summed over the rounds. mcemu writes one when
the drive time is more than 50 ms behind, at most every 10 s (server/clock_driver.cpp).
The one column is the CPU % of the real-clock fleet while only drive 1 moves (measured at every
size): what the quiet drives of a stepping fleet cost (issue 26: ~0; one drive alone is the floor).
The req column is the server CPU per RefGo `TP` round trip on one connection to the last drive of
the idle fleet (REQUESTS requests, default 2000; µs of CPU per request from /proc/<pid>/task/*/schedstat): what a client of
one drive pays for the fleet around it (issue 26).
"""
import http.client
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import time

BINARY = sys.argv[1] if len(sys.argv) > 1 else "build/server/mcemu"
SIZES = [int(a) for a in sys.argv[2:]] or [1, 10, 100, 1000]
WINDOW = float(os.environ.get("WINDOW", "10"))
ROUNDS = int(os.environ.get("ROUNDS", "3"))
ADVANCE_MS = int(os.environ.get("ADVANCE_MS", "60000"))
MOVING_MAX = int(os.environ.get("MOVING_MAX", "100"))
REQUESTS = int(os.environ.get("REQUESTS", "2000"))
TCK = os.sysconf("SC_CLK_TCK")


def ticks(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])


def cpu_ns(pid):
    """CPU time of every thread of the process in ns (/proc/<pid>/task/*/schedstat: ticks are too
    coarse for a few µs per request)."""
    total = 0
    for t in os.listdir(f"/proc/{pid}/task"):
        try:
            total += int(open(f"/proc/{pid}/task/{t}/schedstat").read().split()[0])
        except (FileNotFoundError, ProcessLookupError):
            pass
    return total


def status_kib(pid, key):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith(key + ":"):
            return int(line.split()[1])
    return 0


class Fleet:
    def __init__(self, n, clock="real"):
        self.state = tempfile.TemporaryDirectory(prefix="fleet-bench-")
        # The child writes through its own descriptor, opened for appending; the log is read through
        # a second one. One shared descriptor (as before) shares one file offset: a seek(0) for
        # reading made the child's next line overwrite the start of the log — the 997 or 998
        # "listening" lines of 1000 drives (issue 26).
        log_path = os.path.join(self.state.name, "log")
        child_log = open(log_path, "ab")
        self.log = open(log_path, "r")
        t0 = time.monotonic()
        self.proc = subprocess.Popen([BINARY, "--drives", str(n), "--refgo-port", "0", "--slcan-port", "0",
                                      "--http-port", "0", "--udp-port", "0", "--state-dir", self.state.name,
                                      "--clock", clock, "--max-clients", "8"],
                                     stdout=child_log, stderr=subprocess.STDOUT)
        child_log.close()
        self.http = {}
        self.refgo = {}
        try:
            self._wait_ready(n, t0)
        except BaseException:
            self.proc.kill()
            self.proc.wait()
            raise

    def _wait_ready(self, n, t0):
        while True:
            self.log.seek(0)
            text = self.log.read()
            if " ready" in text or "ready:" in text:
                break
            if self.proc.poll() is not None:
                raise RuntimeError("mcemu exited:\n" + text[-2000:])
            if time.monotonic() - t0 > 120:
                raise RuntimeError("no ready line")
            time.sleep(0.01)
        self.startup_s = time.monotonic() - t0
        for _ in range(500):  # the log file may still be catching up with the ready line
            for m in re.finditer(r"(?:drive (\d+): )?listening: http tcp ([\d.]+):(\d+)", text):
                self.http[int(m.group(1) or 1)] = (m.group(2), int(m.group(3)))
            for m in re.finditer(r"(?:drive (\d+): )?listening: refgo tcp ([\d.]+):(\d+)", text):
                self.refgo[int(m.group(1) or 1)] = (m.group(2), int(m.group(3)))
            if len(self.http) == n:
                break
            time.sleep(0.01)
            self.log.seek(0)
            text = self.log.read()
        if len(self.http) != n:
            missing = [k for k in range(1, n + 1) if k not in self.http][:3]
            lines = [l for l in text.splitlines() if any(f"drive {k}: " in l for k in missing)]
            raise RuntimeError(f"found {len(self.http)} HTTP ports of {n}; drives {missing}: {lines[:12]}")

    def post(self, k, path, body):
        address, port = self.http[k]
        c = http.client.HTTPConnection(address, port, timeout=600)
        c.request("POST", path, body=json.dumps(body), headers={"Content-Type": "application/json"})
        r = c.getresponse()
        data = r.read()
        c.close()
        if r.status != 200:
            raise RuntimeError(f"{path}: {r.status} {data!r}")
        return json.loads(data)

    def start_moving(self, drives=None):
        for k in self.http if drives is None else drives:
            for line in ("PWC", "SP 5000", "RR 20000"):
                self.post(k, "/api/v1/refgo", {"line": line})

    def drive_time_ms(self, k):
        address, port = self.http[k]
        c = http.client.HTTPConnection(address, port, timeout=600)
        c.request("GET", "/api/v1/status")
        body = json.loads(c.getresponse().read())
        c.close()
        return body["timeMs"]

    def lag_warnings(self):
        """How many "behind real time" lines mcemu has logged so far."""
        self.log.seek(0)
        return self.log.read().count("behind real time")

    def request_cpu_us(self, k, count):
        s = socket.create_connection(self.refgo[k])
        a = cpu_ns(self.proc.pid)
        for _ in range(count):
            s.sendall(b"TP\r")
            reply = b""
            while not reply.endswith(b">"):  # the echo, the answer and the ">" prompt
                chunk = s.recv(256)
                if not chunk:
                    raise RuntimeError("RefGo connection closed")
                reply += chunk
        used = cpu_ns(self.proc.pid) - a
        s.close()
        return used / count / 1000

    def cpu_percent(self, seconds):
        a = ticks(self.proc.pid)
        time.sleep(seconds)
        return (ticks(self.proc.pid) - a) / TCK / seconds * 100

    def close(self):
        self.proc.terminate()
        try:
            self.proc.wait(60)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.log.close()
        self.state.cleanup()


def main():
    print(f"cpu: {os.cpu_count()} cores, load {open('/proc/loadavg').read().split()[0]}; window {WINDOW} s, "
          f"{ROUNDS} rounds, medians")
    print(f"{'drives':>6} {'start s':>8} {'idle %':>8} {'moving %':>9} {'RSS MiB':>8} {'KiB/drive':>9} "
          f"{'HWM MiB':>8} {'lag ms':>7} {'logged':>6} {'manual x':>9} {'req us':>7} {'one %':>6}")
    for n in SIZES:
        rows = {"start": [], "idle": [], "moving": [], "lag": [], "logged": [], "rss": [], "hwm": [], "speedup": [], "req": [], "one": []}
        for _ in range(ROUNDS):
            f = Fleet(n)
            try:
                rows["start"].append(f.startup_s)
                time.sleep(1)
                rows["idle"].append(f.cpu_percent(WINDOW))
                rows["req"].append(f.request_cpu_us(n, REQUESTS))
                f.start_moving([1])
                time.sleep(1)
                rows["one"].append(f.cpu_percent(WINDOW))
                if n <= MOVING_MAX:
                    f.start_moving([k for k in f.http if k != 1])
                    time.sleep(1)
                    warned = f.lag_warnings()
                    d0, w0 = f.drive_time_ms(n), time.monotonic()
                    rows["moving"].append(f.cpu_percent(WINDOW))
                    d1, w1 = f.drive_time_ms(n), time.monotonic()
                    rows["lag"].append(max(0.0, (w1 - w0) * 1000 - (d1 - d0)))
                    rows["logged"].append(f.lag_warnings() - warned)
                rows["rss"].append(status_kib(f.proc.pid, "VmRSS") / 1024)
                rows["hwm"].append(status_kib(f.proc.pid, "VmHWM") / 1024)
            finally:
                f.close()
            if n > MOVING_MAX:
                continue
            g = Fleet(n, clock="manual")
            try:
                g.start_moving()
                t0 = time.monotonic()
                g.post(1, "/api/v1/clock/advance", {"ms": ADVANCE_MS})
                rows["speedup"].append(ADVANCE_MS / 1000 / (time.monotonic() - t0))
            finally:
                g.close()
        med = {k: statistics.median(v) if v else float("nan") for k, v in rows.items()}
        logged = sum(rows["logged"]) if rows["logged"] else float("nan")
        # RSS per drive: the process's RSS over the drives (the process itself, ~8 MiB, included)
        print(f"{n:>6} {med['start']:>8.2f} {med['idle']:>8.2f} {med['moving']:>9.1f} {med['rss']:>8.1f} "
              f"{med['rss'] * 1024 / n:>9.0f} {med['hwm']:>8.1f} {med['lag']:>7.0f} {logged:>6.0f} {med['speedup']:>9.1f} {med['req']:>7.0f} {med['one']:>6.1f}", flush=True)


if __name__ == "__main__":
    main()
