#!/usr/bin/env python3
"""What WebSocket subscribers cost mcemu (issue 26 item 2: 100 subscribers of one drive at 20 Hz
< 5 % of a core). One mcemu (one drive, --clock real, the drive at rest) with
"http": {"max_clients": N + 8, "ws_max_clients": N}; N WebSocket clients of this process subscribe
to status (the default) and read every message. mcemu's CPU (user + system from /proc/PID/stat)
over SECONDS is measured with 0 subscribers, then with N, ROUNDS times alternating; the medians
and the difference are printed, with the messages the clients received per second (20 × N when
nothing is lost). A benchmark: it reports, never asserts.

usage: bench/ws_fanout.py [path/to/mcemu] [subscribers, default 100] [seconds, default 10] [rounds, default 3]
"""
import json
import os
import re
import selectors
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "integration"))
from ws_client import WebSocket  # noqa: E402  (the tests' own RFC 6455 client)

BINARY = sys.argv[1] if len(sys.argv) > 1 else "build/server/mcemu"
N = int(sys.argv[2]) if len(sys.argv) > 2 else 100
SECONDS = float(sys.argv[3]) if len(sys.argv) > 3 else 10.0
ROUNDS = int(sys.argv[4]) if len(sys.argv) > 4 else 3
TCK = os.sysconf("SC_CLK_TCK")
LISTEN = re.compile(r"listening: (\w+) tcp [^ ]+:(\d+)")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TCK  # utime, stime


def start(tmp):
    config = os.path.join(tmp, "config.json")
    with open(config, "w") as f:
        json.dump({"http": {"max_clients": N + 8, "ws_max_clients": N}}, f)
    proc = subprocess.Popen([BINARY, "--state-dir", os.path.join(tmp, "state"), "--config", config, "--http-port", "0",
                             "--refgo-port", "0", "--slcan-port", "0", "--udp-port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        m = LISTEN.search(line)
        if m and m.group(1) == "http":
            return proc, int(m.group(2))
    proc.kill()
    raise SystemExit("mcemu did not report its HTTP port")


def frames_in(buf):
    """Complete server frames in buf (unmasked): (count, rest)."""
    n = 0
    while len(buf) >= 2:
        size, head = buf[1] & 0x7F, 2
        if size == 126:
            if len(buf) < 4:
                break
            size, head = int.from_bytes(buf[2:4], "big"), 4
        elif size == 127:
            if len(buf) < 10:
                break
            size, head = int.from_bytes(buf[2:10], "big"), 10
        if len(buf) < head + size:
            break
        n += 1
        buf = buf[head + size:]
    return n, buf


def window(pid, clients):
    """mcemu's CPU % of one core over SECONDS while the clients read; and messages per second."""
    sel = selectors.DefaultSelector()
    bufs = {}
    for ws in clients:
        ws.sock.setblocking(False)
        sel.register(ws.sock, selectors.EVENT_READ)
        bufs[ws.sock] = ws.buf
    messages = 0
    c0, t0 = cpu_seconds(pid), time.monotonic()
    while time.monotonic() - t0 < SECONDS:
        for key, _ in sel.select(timeout=0.1):
            data = key.fileobj.recv(1 << 16)
            if not data:
                raise SystemExit("a subscriber was closed by mcemu")
            n, bufs[key.fileobj] = frames_in(bufs[key.fileobj] + data)
            messages += n
    c1, t1 = cpu_seconds(pid), time.monotonic()
    sel.close()
    return 100.0 * (c1 - c0) / (t1 - t0), messages / (t1 - t0)


def idle_window(pid):
    c0, t0 = cpu_seconds(pid), time.monotonic()
    time.sleep(SECONDS)
    return 100.0 * (cpu_seconds(pid) - c0) / (time.monotonic() - t0)


def main():
    with tempfile.TemporaryDirectory(prefix="mcemu-ws-") as tmp:
        proc, port = start(tmp)
        try:
            idle, busy, rates = [], [], []
            for r in range(ROUNDS):
                idle.append(idle_window(proc.pid))
                clients = [WebSocket(port) for _ in range(N)]
                for ws in clients:
                    ws.recv_type("hello")
                pct, rate = window(proc.pid, clients)
                busy.append(pct)
                rates.append(rate)
                for ws in clients:
                    ws.sock.setblocking(True)
                    ws.close()
                print(f"round {r + 1}: 0 subscribers {idle[-1]:.2f} % of a core, {N} subscribers {pct:.2f} %, "
                      f"{rate:.0f} messages/s", flush=True)
            print(f"ws_fanout: {N} status subscribers of one drive, {SECONDS:.0f} s windows, medians of {ROUNDS}")
            print(f"  mcemu CPU: {statistics.median(idle):.2f} % of a core without, {statistics.median(busy):.2f} % with; "
                  f"the subscribers cost {statistics.median(busy) - statistics.median(idle):.2f} % (goal < 5 %)")
            print(f"  messages received: {statistics.median(rates):.0f}/s (20 Hz x {N} = {20 * N}/s)")
        finally:
            proc.terminate()
            proc.wait(timeout=10)


if __name__ == "__main__":
    main()
