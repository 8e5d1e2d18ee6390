#!/usr/bin/env python3
"""The master lint's cost through the sockets (issue 27 "Cost", docs/lint.md §8.5): two mcemu
processes side by side — `--lint off` and `--lint warn` (every rule at its default severity) —
driven in turn by the same closed-loop client for SECONDS each, ROUNDS rounds, the order rotating.
Both run under the same machine load, so their CPU per request (user + system from
/proc/PID/stat, over all requests of a round) compares directly; the medians are printed. Scenarios:
RefGo `TP` on one connection and an SDO upload of 6041h over SLCAN on one connection (as
bench/echo_ratio). A benchmark: it reports, never asserts.

usage: bench/lint_cost.py [path/to/mcemu] [seconds per round, default 10] [rounds, default 5]
"""
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time

BINARY = sys.argv[1] if len(sys.argv) > 1 else "build/server/mcemu"
SECONDS = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
ROUNDS = int(sys.argv[3]) if len(sys.argv) > 3 else 5
TCK = os.sysconf("SC_CLK_TCK")
LISTEN = re.compile(r"listening: (\w+) tcp [^ ]+:(\d+)")


def start(mode, tmp):
    proc = subprocess.Popen([BINARY, "--state-dir", os.path.join(tmp, mode), "--refgo-port", "0", "--slcan-port", "0",
                             "--http-port", "0", "--udp-port", "0", "--lint", mode],
                            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    ports = {}
    for line in proc.stderr:
        m = LISTEN.search(line)
        if m:
            ports[m.group(1)] = int(m.group(2))
        if " ready" in line:
            break
    threading.Thread(target=lambda: [None for _ in proc.stderr], daemon=True).start()  # keep the log drained
    return proc, ports


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TCK


def closed_loop(port, request, complete, seconds):
    s = socket.create_connection(("127.0.0.1", port))
    s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    n = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        s.sendall(request)
        got = b""
        while not complete(got):
            got += s.recv(4096)
        n += 1
    s.close()
    return n


SCENARIOS = [
    ("RefGo TP, 1 connection", "refgo", b"TP\r", lambda b: b.endswith(b">")),
    ("SDO upload 6041h, 1 connection", "slcan", b"t63284041600000000000\r",
     lambda b: b"t5B2" in b and b.endswith(b"\r")),
]


def main():
    with tempfile.TemporaryDirectory(prefix="mcemu-lint-cost-") as tmp:
        servers = {mode: start(mode, tmp) for mode in ("off", "warn")}
        try:
            print(f"lint_cost: {ROUNDS} rounds of {SECONDS:.0f} s per server and scenario, alternating; "
                  f"load {open('/proc/loadavg').read().split()[0]}")
            for name, service, request, complete in SCENARIOS:
                per = {mode: [] for mode in servers}
                rate = {mode: [] for mode in servers}
                for r in range(ROUNDS):
                    order = ("off", "warn") if r % 2 == 0 else ("warn", "off")
                    for mode in order:
                        proc, ports = servers[mode]
                        c0 = cpu_seconds(proc.pid)
                        n = closed_loop(ports[service], request, complete, SECONDS)
                        c1 = cpu_seconds(proc.pid)
                        per[mode].append((c1 - c0) / n * 1e6)
                        rate[mode].append(n / SECONDS)
                off, on = statistics.median(per["off"]), statistics.median(per["warn"])
                print(f"{name}: lint off {off:.2f} us CPU/request ({statistics.median(rate['off']):.0f}/s), "
                      f"lint warn {on:.2f} us ({statistics.median(rate['warn']):.0f}/s): {100 * (on - off) / off:+.1f} %"
                      f"   rounds off {[round(x, 2) for x in per['off']]} warn {[round(x, 2) for x in per['warn']]}")
        finally:
            for proc, _ in servers.values():
                proc.terminate()
                proc.wait()


if __name__ == "__main__":
    main()
