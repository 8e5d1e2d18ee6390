#!/usr/bin/python3
"""MC BASIC benchmark over the real binary (faulhaber.md §9.9, issue 25). Prints, never asserts.

1. Statements per second of wall time under --clock manual: a tight loop of assignments
   (`a = a + 1`, `b = a`, `c = b * 3 - a`, `GOTO Spin`: 4 statements per pass) with
   faulhaber.basic_statements_per_ms = BUDGET; one POST /api/v1/clock/advance of ADVANCE ms is
   timed; the statements counted are 4 × the change of `a` (read over the binary protocol), so the
   figure is what ran, not what the budget promised. Also at the default budget of 20.
2. A healthy client's latency while a program spins on another drive of the same process (real
   clock): a fleet of [FH_MC5005 (spinning), FH_MC5005 (healthy), MC349 (healthy)]; the healthy
   clients are an SDO read of 6041h over the FAULHABER protocol on drive 2 and RefGo `TP` on drive 3,
   one connection each, CALLS requests per phase (at most PHASE seconds); phases alternate no program / spinning, ROUNDS
   times; medians of the rounds' p50 and p99. Done for each budget in SPIN_BUDGETS (the budget is a
   per-drive config key, so each budget is its own process). PROGRAM=heavy spins the heaviest
   statement there is instead: one 4 KiB line of 219 GETOBJs (2.7 µs each in bench/device_bench).

usage: bench/basic_isolation.py [BINARY]
env: ROUNDS (5), CALLS (3000), PHASE (10 s), BUDGET (250, the largest allowed), ADVANCE (1000),
     SPIN_BUDGETS ("20,250"), PROGRAM ("tight" or "heavy")
"""
import json
import os
import socket
import statistics
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "integration"))
os.environ.setdefault("MCEMU_BIN", sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "build",
                                                                                        "server", "mcemu"))

import faulhaber_client as fc  # noqa: E402
from mcemu_harness import Mcemu, wait_for  # noqa: E402

ROUNDS = int(os.environ.get("ROUNDS", "5"))
CALLS = int(os.environ.get("CALLS", "3000"))
BUDGET = int(os.environ.get("BUDGET", "250"))
ADVANCE = int(os.environ.get("ADVANCE", "1000"))
PHASE = float(os.environ.get("PHASE", "10"))
SPIN_BUDGETS = [int(x) for x in os.environ.get("SPIN_BUDGETS", "20,250").split(",")]
PROGRAM = os.environ.get("PROGRAM", "tight")

SPIN = b":Spin\na = a + 1\nb = a\nc = b * 3 - a\nGOTO Spin\n"
HEAVY = b":Spin\nb = b + 1\na = GETOBJ $6064.00" + b" + GETOBJ $6064.00" * 218 + b"\nGOTO Spin\n"
READ_6041 = bytes.fromhex("53 07 01 01 41 60 00 73 45")


def config_file(doc):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(doc, f)
    f.close()
    return f.name


def pct(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(round(p / 100.0 * (len(s) - 1))))]


def http_ok(m, method, path, body=None, drive=1, content_type="application/json"):
    status, data = m.http(method, path, body, content_type=content_type, timeout=600, drive=drive)
    if status != 200:
        raise RuntimeError(f"{method} {path}: HTTP {status} {data[:200]!r}")
    return json.loads(data)


def statements_per_second(budget, advance_ms):
    cfg = config_file({"faulhaber": {"basic_statements_per_ms": budget}})
    try:
        with Mcemu("--model", "FH_MC5005", "--clock", "manual", "--config", cfg) as m:
            c = fc.open_tcp(m.ports["faulhaber"])
            http_ok(m, "PUT", "/api/v1/faulhaber/programs/1", SPIN, content_type="text/plain")
            http_ok(m, "POST", "/api/v1/faulhaber/programs/1/start", {})
            http_ok(m, "POST", "/api/v1/clock/advance", {"ms": 10})  # warm-up
            rates = []
            for _ in range(ROUNDS):
                a0 = c.read_int(0x3005, 1)
                t0 = time.perf_counter()
                http_ok(m, "POST", "/api/v1/clock/advance", {"ms": advance_ms})
                wall = time.perf_counter() - t0
                ran = 4 * ((c.read_int(0x3005, 1) - a0) & 0xFFFFFFFF)
                rates.append(ran / wall)
            c.close()
            return statistics.median(rates), min(rates), max(rates)
    finally:
        os.unlink(cfg)


class FhReader:
    def __init__(self, address, port):
        self.sock = socket.create_connection((address, port), timeout=10)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def read(self):
        self.sock.sendall(READ_6041)
        got = b""
        while len(got) < 11:
            chunk = self.sock.recv(64)
            if not chunk:
                raise ConnectionError("closed")
            got += chunk
        return got


class RefGoTp:
    def __init__(self, address, port):
        self.sock = socket.create_connection((address, port), timeout=10)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def read(self):
        self.sock.sendall(b"TP\r")
        got = b""
        while not got.endswith(b">"):
            chunk = self.sock.recv(256)
            if not chunk:
                raise ConnectionError("closed")
            got += chunk
        return got


def latencies(client, n):
    """n round trips, or as many as fit in PHASE seconds."""
    out = []
    end = time.monotonic() + PHASE
    for _ in range(n):
        if out and time.monotonic() > end:
            break
        t0 = time.perf_counter()
        client.read()
        out.append((time.perf_counter() - t0) * 1e6)
    return out


def isolation(budget):
    fleet = config_file([{"model": "FH_MC5005", "faulhaber": {"basic_statements_per_ms": budget}},
                         {"model": "FH_MC5005"}, {"model": "MC349"}])
    rows = {k: [] for k in ("base_fh50", "base_fh99", "base_rg50", "base_rg99", "spin_fh50", "spin_fh99",
                            "spin_rg50", "spin_rg99", "spin_cpu", "behind")}
    try:
        with Mcemu("--fleet", fleet) as m:
            wait_for(lambda: len(m.drives) == 3 and "refgo" in m.drives[3], what="three drives")
            fh = FhReader(*m.drives[2]["faulhaber"])
            rg = RefGoTp(*m.drives[3]["refgo"])
            program = HEAVY if PROGRAM == "heavy" else SPIN
            http_ok(m, "PUT", "/api/v1/faulhaber/programs/1", program, content_type="text/plain")
            latencies(fh, 300)
            latencies(rg, 300)
            tck = os.sysconf("SC_CLK_TCK")
            for _ in range(ROUNDS):
                fh_b, rg_b = latencies(fh, CALLS), latencies(rg, CALLS)
                http_ok(m, "POST", "/api/v1/faulhaber/programs/1/start", {})
                pid = m.proc.pid
                fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
                c0, t0 = int(fields[11]) + int(fields[12]), time.monotonic()
                clock0 = http_ok(m, "GET", "/api/v1/clock", drive=2)["timeMs"]
                fh_s, rg_s = latencies(fh, CALLS), latencies(rg, CALLS)
                clock1 = http_ok(m, "GET", "/api/v1/clock", drive=2)["timeMs"]
                wall = time.monotonic() - t0
                fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
                cpu = 100.0 * ((int(fields[11]) + int(fields[12])) - c0) / tck / wall
                state = http_ok(m, "POST", "/api/v1/faulhaber/stop", {})
                assert state["programs"][0]["state"] == "stopped", state
                for k, v in (("base_fh50", pct(fh_b, 50)), ("base_fh99", pct(fh_b, 99)), ("base_rg50", pct(rg_b, 50)),
                             ("base_rg99", pct(rg_b, 99)), ("spin_fh50", pct(fh_s, 50)), ("spin_fh99", pct(fh_s, 99)),
                             ("spin_rg50", pct(rg_s, 50)), ("spin_rg99", pct(rg_s, 99)), ("spin_cpu", cpu),
                             ("behind", 100.0 * (clock1 - clock0) / (wall * 1000.0))):
                    rows[k].append(v)
    finally:
        os.unlink(fleet)
    return {k: statistics.median(v) for k, v in rows.items()}


def main():
    print(f"load before: {open('/proc/loadavg').read().strip()}")
    for budget, advance in ((BUDGET, ADVANCE), (20, max(ADVANCE * 50, 1000))):
        med, lo, hi = statements_per_second(budget, advance)
        print(f"tight loop, {budget} statements/ms, advance {advance} ms: {med / 1e6:.1f} M statements/s of wall time"
              f" (median of {ROUNDS}; min {lo / 1e6:.1f}, max {hi / 1e6:.1f})", flush=True)
    print(f"\nhealthy clients on drives 2 and 3 while drive 1 spins (medians of {ROUNDS} rounds, {CALLS} requests "
          f"per phase, microseconds; program {PROGRAM})")
    print(f"{'budget':>8} {'FH SDO p50':>22} {'FH SDO p99':>22} {'RefGo TP p50':>22} {'RefGo TP p99':>22} "
          f"{'CPU %':>6} {'drive time %':>12}")
    for budget in SPIN_BUDGETS:
        r = isolation(budget)
        print(f"{budget:>8} {r['base_fh50']:>10.1f} → {r['spin_fh50']:>9.1f} {r['base_fh99']:>10.1f} → "
              f"{r['spin_fh99']:>9.1f} {r['base_rg50']:>10.1f} → {r['spin_rg50']:>9.1f} {r['base_rg99']:>10.1f} → "
              f"{r['spin_rg99']:>9.1f} {r['spin_cpu']:>6.0f} {r['behind']:>12.0f}", flush=True)
    print(f"load after: {open('/proc/loadavg').read().strip()}")


if __name__ == "__main__":
    main()
