"""Load (issue 12): 1,000 concurrent RefGo clients (`--max-clients 1000`) doing 100 commands each,
every reply byte-exact, with mcemu's memory bounded; and 100 SLCAN clients doing SDO uploads at
the same time. One client thread per test multiplexes every socket (selectors); every wait is
bounded. Throughput and latency are the benchmarks' business (bench/), not asserted here.

mcemu is started with a soft file-descriptor limit of 1024 (inherited from this process): serving
1,000 clients proves that it raises the limit itself (server/main.cpp).
"""
import json
import os
import resource
import selectors
import socket
import subprocess
import time
import unittest

from mcemu_harness import MCEMU, Mcemu

# Commands whose replies on an idle, fresh MC349 are fixed bytes (refgo.md §14).
REFGO = [(b"TS", b"TS\r\n0\r\n>"), (b"TPSR", b"TPSR\r\n00000002\r\n>"), (b"OR1018,1", b"OR1018,1\r\nOR1018,1,1339\r\n>"),
         (b"TI3", b"TI3\r\n0\r\n>"), (b"XYZ", b">"), (b"OR1234,0", b"OR1234,0\r\nOR1234,0,ERROR,06020000h\r\n>"),
         (b"OR1008,0", b"OR1008,0\r\nOR1008,0,MC349_ETH_RE\r\n>"), (b"TP", b"TP\r\n0\r\n>"),
         (b"OR6041,0,h", b"OR6041,0,H\r\nOR6041,0,40h\r\n>"), (b"OW6041,0,5", b"OW6041,0,5\r\nOW6041,0,5,ERROR,06010002h\r\n>")]


def status_kib(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


def soft_nofile(pid):
    with open(f"/proc/{pid}/limits") as f:
        for line in f:
            if line.startswith("Max open files"):
                return int(line.split()[3])
    return 0


class Clients:
    """Many non-blocking client sockets, each waiting for a reply of known length."""

    def __init__(self, port, n):
        self.sel = selectors.DefaultSelector()
        self.socks = []
        for i in range(n):
            s = socket.create_connection(("127.0.0.1", port), timeout=30)
            s.setblocking(False)
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.socks.append(s)
            self.sel.register(s, selectors.EVENT_READ, i)

    def close(self):
        for s in self.socks:
            self.sel.unregister(s)
            s.close()
        self.sel.close()


class ThousandRefgoClients(unittest.TestCase):
    def test_thousand_clients_hundred_commands_each_byte_exact(self):
        n, rounds = 1000, 100
        soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        if hard < 2 * n + 100:
            self.skipTest(f"the hard file-descriptor limit {hard} is too low for {n} clients and mcemu")
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(1024, hard), hard))  # inherited by mcemu
        try:
            m = Mcemu("--max-clients", str(n))
        finally:
            resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
        with m:
            pid = m.proc.pid
            self.assertGreaterEqual(soft_nofile(pid), 2 * n, "mcemu raises its soft file-descriptor limit")
            rss_idle = status_kib(pid, "VmRSS")
            c = Clients(m.ports["refgo"], n)
            try:
                rss_connected = status_kib(pid, "VmRSS")
                step = [0] * n
                bufs = [b""] * n
                errors = []

                def send_next(i):
                    cmd, _ = REFGO[(i + step[i]) % len(REFGO)]
                    c.socks[i].sendall(cmd + b"\r")

                for i in range(n):
                    send_next(i)
                done = 0
                deadline = time.monotonic() + 600
                while done < n and not errors:
                    self.assertLess(time.monotonic(), deadline, f"{done} of {n} clients finished in time")
                    for key, _ in c.sel.select(timeout=5):
                        i = key.data
                        chunk = key.fileobj.recv(65536)
                        if not chunk:
                            errors.append((i, "closed", bufs[i]))
                            break
                        bufs[i] += chunk
                        _, want = REFGO[(i + step[i]) % len(REFGO)]
                        if not bufs[i].endswith(b">"):  # no request here contains '>'
                            continue
                        if bufs[i] != want:
                            errors.append((i, step[i], bufs[i], want))
                            break
                        bufs[i] = b""
                        step[i] += 1
                        if step[i] == rounds:
                            done += 1
                        else:
                            send_next(i)
                self.assertEqual(errors[:3], [])
                rss_busy = status_kib(pid, "VmRSS")
                hwm = status_kib(pid, "VmHWM")
            finally:
                c.close()
            print(f"\n1000 RefGo clients × 100 commands: mcemu VmRSS idle {rss_idle} KiB, 1000 connected "
                  f"{rss_connected} KiB, after the run {rss_busy} KiB, peak (VmHWM) {hwm} KiB", flush=True)
            self.assertLess(hwm - rss_idle, 64 * 1024, "memory per connection stays small")


def sdo_line(index, sub):
    data = bytes([0x40, index & 0xFF, index >> 8, sub, 0, 0, 0, 0])
    return b"t6328" + data.hex().upper().encode() + b"\r"


class HundredSlcanClients(unittest.TestCase):
    def test_hundred_sdo_clients_at_once(self):
        n, uploads = 100, 20
        doc = json.loads(subprocess.run([MCEMU, "--dump-od", "--model", "MC349"], capture_output=True, check=True,
                                        timeout=30).stdout)
        sizes = {"UNSIGNED8": 1, "INTEGER8": 1, "UNSIGNED16": 2, "INTEGER16": 2, "UNSIGNED32": 4, "INTEGER32": 4}
        objects = [(e["index"], e["sub"]) for e in doc["entries"]
                   if e["class"] in ("const", "param") and e["access"] in ("ro", "rw", "const") and e["type"] in sizes]
        self.assertGreaterEqual(len(objects), n)
        objects = objects[:n]
        with Mcemu("--max-clients", str(n + 1)) as m:
            port = m.ports["slcan"]
            # what each object's upload answers when asked alone
            ref = socket.create_connection(("127.0.0.1", port), timeout=10)
            expected = {}
            buf = b""
            for index, sub in objects:
                ref.sendall(sdo_line(index, sub))
                want_prefix = b"t5B28"
                while True:
                    lines = buf.split(b"\r")
                    hit = [l for l in lines[:-1] if l.startswith(want_prefix) and
                           l[7:13] == f"{index & 0xFF:02X}{index >> 8:02X}{sub:02X}".encode()]
                    if hit:
                        expected[(index, sub)] = hit[0]
                        buf = b""
                        break
                    chunk = ref.recv(4096)
                    self.assertTrue(chunk)
                    buf += chunk
            ref.close()

            c = Clients(port, n)
            try:
                count = [0] * n
                bufs = [b""] * n
                acked = [False] * n
                answered = [False] * n
                errors = []
                for i in range(n):
                    c.socks[i].sendall(sdo_line(*objects[i]))
                done = 0
                seen_frames = 0
                deadline = time.monotonic() + 300
                while done < n and not errors:
                    self.assertLess(time.monotonic(), deadline, f"{done} of {n} SDO clients finished in time")
                    for key, _ in c.sel.select(timeout=5):
                        i = key.data
                        chunk = key.fileobj.recv(65536)
                        if not chunk:
                            errors.append((i, "closed"))
                            break
                        *lines, bufs[i] = (bufs[i] + chunk).split(b"\r")
                        mine = f"{objects[i][0] & 0xFF:02X}{objects[i][0] >> 8:02X}{objects[i][1]:02X}".encode()
                        for line in lines:
                            if line == b"z":
                                acked[i] = True
                            elif line.startswith(b"t5B28"):
                                seen_frames += 1
                                if line[7:13] == mine and count[i] < uploads:
                                    if line != expected[objects[i]]:
                                        errors.append((i, line, expected[objects[i]]))
                                    answered[i] = True
                            elif line.startswith(b"t"):
                                continue  # heartbeats, EMCY: none expected, harmless
                            else:
                                errors.append((i, "unexpected line", line))
                        if acked[i] and answered[i]:
                            acked[i] = answered[i] = False
                            count[i] += 1
                            if count[i] == uploads:
                                done += 1
                            else:
                                c.socks[i].sendall(sdo_line(*objects[i]))
                self.assertEqual(errors[:3], [])
            finally:
                c.close()
            self.assertEqual(count, [uploads] * n)
            # every response goes to every session (slcan-canopen.md §3.7)
            self.assertGreaterEqual(seen_frames, n * uploads)
            print(f"\n100 SLCAN clients × {uploads} SDO uploads: {seen_frames} response frames delivered, "
                  f"mcemu VmHWM {status_kib(m.proc.pid, 'VmHWM')} KiB", flush=True)


if __name__ == "__main__":
    unittest.main()
