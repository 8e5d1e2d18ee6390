"""RefGo on TCP against the real mcemu binary, driven by netcat (refgo.md §14 transcripts, §15).

Every conversation goes through `nc` (Debian's netcat-openbsd), as a user's shell script would;
a few acceptance tests that need socket-level control (single write per reply, mctk and XENAX
client emulation, backpressure) use Python sockets.
"""
import json
import os
import random
import socket
import tempfile
import threading
import time
import unittest

from mcemu_harness import SANITIZED, Mcemu, connect, fill_trace_ring, wait_for
from nc_client import Nc, nc_once, vector_regex


def config_file(doc):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(doc, f)
    f.close()
    return f.name


def poll(nc, line, want, timeout=30.0):
    """Repeats `line` until its reply equals `want` (bytes); returns the replies seen before."""
    seen = []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        r = nc.request(line)
        if r == want:
            return seen
        seen.append(r)
        time.sleep(0.005)
    raise TimeoutError(f"{line!r} never answered {want!r}; last {seen[-3:]!r}")


class Transcripts(unittest.TestCase):
    """refgo.md §14.1 and §14.2, byte by byte with {TP} as a regex."""

    def test_2021_session(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            for line in ("REF35", "SP720", "AC5000", "DE1000", "G360"):
                self.assertEqual(nc.request(line), line.encode() + b"\r\n>")
            # rows 6–8 in one segment, so that row 7 sees the move just started whatever the host's
            # load (current firmware: bit 8 set); a line's effect is visible to the next (§2.5)
            nc.send(b"G-7200\rTPSR\rTP\r")
            g, tpsr, tp = nc.replies(3)
            self.assertEqual(g, b"G-7200\r\n>")
            self.assertEqual(tpsr, b"TPSR\r\n00000106\r\n>")
            self.assertRegex(tp, vector_regex(b"TP\r\n{TP}\r\n>"))
            poll(nc, "TPSR", b"TPSR\r\n0000010a\r\n>")
            self.assertEqual(nc.request("TP"), b"TP\r\n-7200\r\n>")
            self.assertEqual(nc.request("PQ"), b"PQ\r\n>")
            self.assertEqual(nc.request("OW3511,8,110"), b"OW3511,8,110\r\nOW3511,8,110,OK\r\n>")
            self.assertEqual(nc.request("OR3511,8"), b"OR3511,8\r\nOR3511,8,110\r\n>")
            self.assertEqual(nc.request("OW3511,8,120"), b"OW3511,8,120\r\nOW3511,8,120,OK\r\n>")
            self.assertEqual(nc.request("OR3511,8"), b"OR3511,8\r\nOR3511,8,120\r\n>")

    def test_2022_block_homing_session(self):
        cfg = config_file({"plant": {"stops": [-30000, 1000000]}})
        try:
            with Mcemu("--config", cfg) as m, Nc(m.ports["refgo"]) as nc:
                self.assertEqual(nc.request(""), b">")
                self.assertEqual(nc.request("PWC"), b"PWC\r\n>")
                for ow in ("OW6091,1,1", "OW6091,2,1", "OW6092,1,360", "OW6092,2,1", "OW6099,1,200",
                           "OW609A,0,400", "OW6073,0,200", "OW607C,0,-10"):
                    self.assertEqual(nc.request(ow), f"{ow}\r\n{ow},OK\r\n>".encode())
                self.assertEqual(nc.request("REF-19"), b"REF-19\r\n>")
                tp = vector_regex(b"TP\r\n{TP}\r\n>")
                searching = False
                deadline = time.monotonic() + 30
                while True:
                    self.assertLess(time.monotonic(), deadline, "homing never reached the block")
                    self.assertRegex(nc.request("TP"), tp)
                    r = nc.request("TPSR")
                    self.assertIn(r, (b"TPSR\r\n00000106\r\n>", b"TPSR\r\n0000010a\r\n>", b"TPSR\r\n00000102\r\n>"))
                    searching |= r == b"TPSR\r\n00000106\r\n>"
                    if r == b"TPSR\r\n0000010a\r\n>" and searching:
                        break
                self.assertTrue(searching)
                self.assertRegex(nc.request("TP"), tp)
                self.assertEqual(nc.request("OW6073,0,1000"), b"OW6073,0,1000\r\nOW6073,0,1000,OK\r\n>")
                nc.send(b"G0\rTPSR\r")
                self.assertEqual(nc.replies(2), [b"G0\r\n>", b"TPSR\r\n00000106\r\n>"])
                poll(nc, "TPSR", b"TPSR\r\n0000010a\r\n>")
                self.assertEqual(nc.request("TP"), b"TP\r\n0\r\n>")
        finally:
            os.unlink(cfg)

    def test_tt_tv_without_script(self):
        # §14.3, second half: no script attached, so TT and TV are unknown words.
        with Mcemu() as m:
            out, _ = nc_once(m.ports["refgo"], b"TT\rTV\r")
            self.assertEqual(out, b">>")


# refgo.md §14.5 (and the parts of §14.4 that need no set-up), one nc session each.
VECTORS_14_5 = [
    (b"tp\r", b"TP\r\n{TP}\r\n>"),
    (b"TP\r\n", b"TP\r\n{TP}\r\n>"),
    (b"TP\n", b"TP\r\n{TP}\r\n>"),
    (b"  \r", b">"),
    (b"XYZ\r", b">"),
    (b"A" * 300 + b"\r", b">"),
    (b"OW6041,0,5\r", b"OW6041,0,5\r\nOW6041,0,5,ERROR,06010002h\r\n>"),
    (b"OR1234,0\r", b"OR1234,0\r\nOR1234,0,ERROR,06020000h\r\n>"),
    (b"OR6041,9\r", b"OR6041,9\r\nOR6041,9,ERROR,06090011h\r\n>"),
    (b"OW6060,0,99\r", b"OW6060,0,99\r\nOW6060,0,99,ERROR,06090030h\r\n>"),
    (b"OW340B,1,300\r", b"OW340B,1,300\r\nOW340B,1,300,ERROR,06090031h\r\n>"),
    (b"OW6040,0,X\r", b"OW6040,0,X\r\nOW6040,0,X,ERROR,08000000h\r\n>"),
    (b"OW607C,0,-10\rOR607C,0,h\r", b"OW607C,0,-10\r\nOW607C,0,-10,OK\r\n>OR607C,0,H\r\nOR607C,0,fffffff6h\r\n>"),
    (b"OR1008,0\r", b"OR1008,0\r\nOR1008,0,MC349_ETH_RE\r\n>"),
    (b"SO7\r", b"SO7\r\nSO7,ERROR,06090030h\r\n>"),
    (b"G1000\rTS\r", b"G1000\r\n>TS\r\n2\r\n>"),
    (b" tp\r", b" TP\r\n{TP}\r\n>"),
    (b"SO\t7\r", b"SO 7\r\nSO 7,ERROR,06090030h\r\n>"),
    (b"TP\n\r", b"TP\r\n{TP}\r\n>>"),
    (b"OR1234,0,h\r", b"OR1234,0,H\r\nOR1234,0,ERROR,06020000h\r\n>"),
    (b"REF200\r", b"REF200\r\nREF200,ERROR,06090031h\r\n>"),
    (b"SP4294967296\r", b"SP4294967296\r\nSP4294967296,ERROR,06090030h\r\n>"),
    # §14.4
    (b"TP\r", b"TP\r\n{TP}\r\n>"),
    (b"OW6067,0,100\rOR6067,0\r", b"OW6067,0,100\r\nOW6067,0,100,OK\r\n>OR6067,0\r\nOR6067,0,100\r\n>"),
    (b"OW 60FE,1,65536\r", b"OW 60FE,1,65536\r\nOW 60FE,1,65536,OK\r\n>"),
    (b"OW3410,1,4242\rOR3410h,1h\r", b"OW3410,1,4242\r\nOW3410,1,4242,OK\r\n>OR3410H,1H\r\nOR3410H,1H,4242\r\n>"),
    (b"OW3510H,1H,65536\r", b"OW3510H,1H,65536\r\nOW3510H,1H,65536,OK\r\n>"),
]


class Vectors(unittest.TestCase):
    def test_vectors_of_14_4_and_14_5(self):
        with Mcemu() as m:
            for request, expected in VECTORS_14_5:
                with self.subTest(request=request):
                    # a fresh emulator state per vector is not needed: each one sets what it reads
                    # nc -N returns only once mcemu closes after the FIN (else nc_once times out)
                    out, _ = nc_once(m.ports["refgo"], request, timeout=30)
                    self.assertRegex(out, vector_regex(expected))

    def test_statusword_vectors_of_14_4(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            self.assertEqual(nc.request("PWC"), b"PWC\r\n>")
            poll(nc, "OR6041,0,h", b"OR6041,0,H\r\nOR6041,0,427h\r\n>")
            self.assertEqual(nc.request("OW6081,0,60"), b"OW6081,0,60\r\nOW6081,0,60,OK\r\n>")
            self.assertEqual(nc.request("OW607A,0,655360"), b"OW607A,0,655360\r\nOW607A,0,655360,OK\r\n>")
            # the first 100 ms show set-point acknowledge (1127h), then 127h while moving (MAN §5.2)
            nc.send(b"OW6040,0,31\rOR6041,0,h\r")
            self.assertEqual(nc.replies(2), [b"OW6040,0,31\r\nOW6040,0,31,OK\r\n>",
                                             b"OR6041,0,H\r\nOR6041,0,1127h\r\n>"])
            poll(nc, "OR6041,0,h", b"OR6041,0,H\r\nOR6041,0,127h\r\n>", timeout=2)

    def test_input_vectors_of_14_4(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            nc.request("OW3510,1,327680")  # virtual IN1 and IN3
            poll(nc, "OR60FD,0,h", b"OR60FD,0,H\r\nOR60FD,0,50000h\r\n>")
            self.assertEqual(nc.request("TI3"), b"TI3\r\n1\r\n>")
            self.assertEqual(nc.request("TI"), b"TI\r\n0005\r\n>")
            nc.request("OW3510,1,131072")  # IN2 only
            poll(nc, "OR 60FD,0", b"OR 60FD,0\r\nOR 60FD,0,131072\r\n>")

    def test_error_register_after_under_voltage(self):
        cfg = config_file({"plant": {"supply_nominal_V": 10}})
        try:
            with Mcemu("--config", cfg) as m, Nc(m.ports["refgo"]) as nc:
                poll(nc, "OR603F,0,h", b"OR603F,0,H\r\nOR603F,0,3221h\r\n>")
                self.assertEqual(nc.request("TS"), b"TS\r\n9\r\n>")
                self.assertEqual(nc.request("TPSR"), b"TPSR\r\n00000003\r\n>")
                self.assertEqual(nc.request("G1000"), b"G1000\r\n>")  # valid, no effect in F (§10)
                self.assertEqual(nc.request("TS"), b"TS\r\n9\r\n>")
        finally:
            os.unlink(cfg)


class Framing(unittest.TestCase):
    def test_pipelined_hundred_lines_mixed_terminators(self):
        with Mcemu() as m:
            ends = [b"\r", b"\n", b"\r\n"]
            request = b""
            expected = b""
            for i in range(100):
                request += b"OW3410,1,%d" % i + ends[i % 3] + b"OR3410,1" + ends[(i + 1) % 3]
                expected += b"OW3410,1,%d\r\nOW3410,1,%d,OK\r\n>OR3410,1\r\nOR3410,1,%d\r\n>" % (i, i, i)
            out, _ = nc_once(m.ports["refgo"], request)
            self.assertEqual(out, expected)

    def test_half_close_with_nc(self):
        # §15.10: the lines before the FIN are answered, then mcemu closes; an unterminated line is not.
        # nc -N exits only when mcemu closes its side, so nc_once returning is the proof (no
        # wall-clock bound here: tests run in parallel on loaded machines).
        with Mcemu() as m:
            out, _ = nc_once(m.ports["refgo"], b"TP\r\nTS\n", timeout=30)
            self.assertRegex(out, vector_regex(b"TP\r\n{TP}\r\n>TS\r\n0\r\n>"))
            out, _ = nc_once(m.ports["refgo"], b"TP", timeout=30)
            self.assertEqual(out, b"")

    def test_garbage_and_overlong_lines_keep_the_session(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            rnd = random.Random(4)
            for _ in range(50):
                junk = bytes(rnd.choice([b for b in range(256) if b not in (13, 10, ord(">"))]) for _ in range(40))
                nc.send(junk + b"\r")
                nc.replies(1)
                self.assertRegex(nc.request("TP"), vector_regex(b"TP\r\n{TP}\r\n>"))
            nc.send(b"OR6064,0" + b" " * 300 + b"\r")
            self.assertEqual(nc.replies(1), [b">"])
            # control bytes are removed, except TAB, which becomes a (leading) space
            nc.send(bytes(range(0, 32)).replace(b"\r", b"").replace(b"\n", b"") + b"TS\x7f\r")
            self.assertEqual(nc.replies(1), [b" TS\r\n0\r\n>"])
            line = b"OR6064,0" + b" " * 247  # 255 bytes: still executed
            nc.send(line + b"\r")
            self.assertRegex(nc.replies(1)[0], vector_regex(line + b"\r\nOR6064,0,{TP}\r\n>"))

    def test_store_answers_when_durable_and_holds_back_later_lines(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            nc.send(b"OW6083,0,4321\rOW1010,1,1702257011\rTS\rOR6083,0\r")
            replies = nc.replies(4)
            self.assertEqual(replies, [b"OW6083,0,4321\r\nOW6083,0,4321,OK\r\n>",
                                       b"OW1010,1,1702257011\r\nOW1010,1,1702257011,OK\r\n>",
                                       b"TS\r\n0\r\n>", b"OR6083,0\r\nOR6083,0,4321\r\n>"])
            with open(os.path.join(m.state_dir, "drive-1.json")) as f:
                state = json.load(f)
            self.assertIn("4321", json.dumps(state))
            self.assertEqual(nc.request("OW1010,1,5"), b"OW1010,1,5\r\nOW1010,1,5,ERROR,08000020h\r\n>")
            self.assertEqual(nc.request("G100"), b"G100\r\n>")
            self.assertEqual(nc.request("OW1011,1,1684107116"),
                             b"OW1011,1,1684107116\r\nOW1011,1,1684107116,ERROR,08000022h\r\n>")


class Clients(unittest.TestCase):
    def test_disconnect_mid_move_does_not_stop_the_move(self):
        with Mcemu() as m:
            with Nc(m.ports["refgo"]) as a:
                self.assertEqual(a.request("SP100"), b"SP100\r\n>")
                self.assertEqual(a.request("G327680"), b"G327680\r\n>")  # five turns at 100 rpm: 3 s
                self.assertEqual(a.request("TS"), b"TS\r\n2\r\n>")
            with Nc(m.ports["refgo"]) as b:
                self.assertEqual(b.request("TS"), b"TS\r\n2\r\n>")
                poll(b, "TP", b"TP\r\n327680\r\n>", timeout=15)
                self.assertEqual(b.request("TS"), b"TS\r\n1\r\n>")

    def test_hundred_concurrent_nc_clients(self):
        n = 100
        with Mcemu("--max-clients", str(n)) as m:
            clients = [Nc(m.ports["refgo"]) for _ in range(n)]
            try:
                wait_for(lambda: all(c.proc.poll() is None for c in clients), what="nc clients")
                for i, c in enumerate(clients):  # every client proves its connection is served
                    self.assertEqual(c.request(f"OW340F,1,{i}"), f"OW340F,1,{i}\r\nOW340F,1,{i},OK\r\n>".encode())
                for rnd in range(10):
                    for i, c in enumerate(clients):
                        c.send(f"TP\rOR3410,1\rOR1018,1\rOR6041,0,h\rTI{i % 10 + 1}\r".encode())
                    for i, c in enumerate(clients):
                        r = c.replies(5, timeout=10)
                        self.assertRegex(r[0], vector_regex(b"TP\r\n{TP}\r\n>"))
                        self.assertEqual(r[1], b"OR3410,1\r\nOR3410,1,0\r\n>")
                        self.assertEqual(r[2], b"OR1018,1\r\nOR1018,1,1339\r\n>")
                        self.assertRegex(r[3], rb"\AOR6041,0,H\r\nOR6041,0,[0-9a-f]+h\r\n>\Z")
                        self.assertEqual(r[4], f"TI{i % 10 + 1}\r\n0\r\n>".encode())
                # one more than the limit is closed at once without a byte
                extra = Nc(m.ports["refgo"])
                extra.send(b"TP\r")
                wait_for(extra.eof, timeout=5, what="the 101st connection closed")
                self.assertEqual(extra.take_all(), b"")
                extra.close()
            finally:
                for c in clients:
                    c.close()

    def test_eight_clients_polling_and_a_ninth_refused(self):
        # §15.6 with the default limit: every client gets only its own replies, in order. The ninth
        # connects once all eight have been served (a barrier, not a sleep), and the eight keep
        # polling until it has been refused and at least 2 s have passed.
        with Mcemu() as m:
            errors = []
            min_end = time.monotonic() + 2.0
            connected = threading.Barrier(9, timeout=30)
            ninth_checked = threading.Event()

            def client(k):
                try:
                    s = connect(m.ports["refgo"])
                    f = s.makefile("rb")
                    i = 0
                    while i == 0 or time.monotonic() < min_end or not ninth_checked.is_set():
                        s.sendall(b"OW340F,%d,%d\rOR340F,%d\rTPSR\r" % (k + 1, i, k + 1))
                        want = (b"OW340F,%d,%d\r\nOW340F,%d,%d,OK\r\n>OR340F,%d\r\nOR340F,%d,%d\r\n>"
                                % (k + 1, i, k + 1, i, k + 1, k + 1, i))
                        got = f.read(len(want))
                        if got != want:
                            errors.append((k, got, want))
                            return
                        tpsr = f.read(len(b"TPSR\r\n00000002\r\n>"))
                        if not tpsr.startswith(b"TPSR\r\n000001") and tpsr != b"TPSR\r\n00000002\r\n>":
                            errors.append((k, tpsr))
                            return
                        if i == 0:
                            connected.wait()
                        i += 1
                    s.close()
                except Exception as e:  # noqa: BLE001 - reported below
                    errors.append((k, repr(e)))
                    connected.abort()

            threads = [threading.Thread(target=client, args=(k,)) for k in range(8)]
            for t in threads:
                t.start()
            try:
                try:
                    connected.wait()  # all eight connected and served
                except threading.BrokenBarrierError:
                    self.fail(f"a client failed before the ninth connected: {errors}")
                ninth = connect(m.ports["refgo"])
                ninth.settimeout(30)
                try:
                    data = ninth.recv(10)  # EOF (or a reset): closed without a byte
                except ConnectionResetError:
                    data = b""
                self.assertEqual(data, b"")
                ninth.close()
            finally:
                ninth_checked.set()
                for t in threads:
                    t.join(timeout=60)
            self.assertEqual(errors, [])


class ClientCompatibility(unittest.TestCase):
    def test_single_write_per_reply(self):
        # §15.2: each reply arrives in one recv on loopback.
        with Mcemu() as m:
            s = connect(m.ports["refgo"])
            s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            s.settimeout(0.001)
            commands = ["TP", "TS", "TPSR", "OR6041,0,h", "OR1008,0", "OW6083,0,1000", "XYZ", "TI", "SP720", "OR1234,0"]
            for i in range(1000):
                cmd = commands[i % len(commands)]
                s.sendall(cmd.encode() + b"\r")
                chunks = []
                deadline = time.monotonic() + 5
                while not (chunks and chunks[-1].endswith(b">")):
                    self.assertLess(time.monotonic(), deadline)
                    try:
                        chunk = s.recv(4096)
                    except socket.timeout:
                        continue
                    self.assertTrue(chunk)
                    chunks.append(chunk)
                self.assertEqual(len(chunks), 1, f"{cmd}: reply in {len(chunks)} pieces {chunks!r}")
            s.close()

    def test_mctk_refgo_client_pattern(self):
        # §15.3: Fullmo mctk's RefgoClient I/O, reproduced.
        with Mcemu() as m:
            s = connect(m.ports["refgo"])

            def command(cmd):
                s.settimeout(0.05)
                try:
                    while s.recv(4096):
                        pass
                except socket.timeout:
                    pass
                s.sendall(cmd.encode() + b"\r")
                time.sleep(0.15)
                s.settimeout(1)
                return s.recv(4096).decode()

            def read_object(index, sub):
                for line in command(f"OR{index:X}h,{sub:X}h").splitlines():
                    if line.startswith("OR"):
                        parts = line.split(",")
                        if len(parts) >= 3:
                            try:
                                return int(parts[2])
                            except ValueError:
                                return None
                return None

            def write_object(index, sub, value):
                reply = command(f"OW{index:X}h,{sub:X}h,{value}")
                return "error" not in reply.lower() and "?" not in reply

            def first_value(cmd):
                for line in command(cmd).splitlines():
                    line = line.strip()
                    if line and line != ">" and line != cmd:
                        return int(line)
                return None

            self.assertTrue(write_object(0x3410, 1, 4242))
            self.assertEqual(read_object(0x3410, 1), 4242)
            self.assertFalse(write_object(0x6041, 0, 5))
            self.assertIsNone(read_object(0x1234, 0))
            self.assertEqual(first_value("TS"), 0)
            self.assertIsInstance(first_value("TP"), int)
            command("G1000")
            wait_for(lambda: first_value("TS") == 1, timeout=5, what="TS 1 after a short move")
            self.assertEqual(first_value("TP"), 1000)
            s.close()

    @unittest.skipUnless(os.environ.get("MCEMU_MCTK_DIR"), "MCEMU_MCTK_DIR names no movingcap-code-suite checkout")
    def test_unmodified_mctk_refgo_client(self):
        # §15.3, second half: Fullmo's own RefgoClient, when a checkout is provided (not committed).
        import sys
        sys.path.insert(0, os.path.join(os.environ["MCEMU_MCTK_DIR"], "testing"))
        from mctk.refgo import RefgoClient  # noqa: E402 - third-party code found at run time
        with Mcemu() as m, RefgoClient("127.0.0.1", port=m.ports["refgo"]) as drive:
            self.assertTrue(drive.write_object(0x3410, 1, 4242))
            self.assertEqual(drive.read_object(0x3410, 1), 4242)
            self.assertFalse(drive.write_object(0x6041, 0, 5))
            self.assertIsNone(drive.read_object(0x1234, 0))
            self.assertEqual(drive.tell_status(), 0)
            self.assertIsInstance(drive.tell_position(), int)

    def test_xenax_style_client(self):
        # §15.4: XFATE's SendCommand / ProcessEchoCommand pattern.
        with Mcemu() as m:
            s = connect(m.ports["refgo"])
            s.settimeout(0.25)

            def send(cmd):
                s.sendall(cmd.encode() + b"\r")
                got = b""
                while True:
                    chunk = s.recv(256)
                    got += chunk
                    if b">" in chunk:
                        break
                text = got.decode("latin-1")
                if cmd not in text:
                    raise RuntimeError(f"echo missing for {cmd}: {text!r}")
                rest = text.replace(cmd, "", 1)
                if "?" in rest or "#" in rest:
                    raise RuntimeError(f"error reply to {cmd}: {text!r}")
                return text

            for cmd in ("SP500", "AC5000", "G1000", "WA100", "GW", "SM", "PWC", "JP", "JN", "SM", "REF35"):
                send(cmd)
            self.assertIsInstance(int(send("TP").split("\r\n")[1]), int)
            self.assertEqual(int(send("TPSR").split("\r\n")[1], 16) & 0x102, 0x102)
            with self.assertRaises(RuntimeError):
                send("SCRV20")  # a XENAX command RefGo lacks: '>' only, the echo check fails
            s.close()

    def test_backpressure_from_a_client_that_never_reads(self):
        # §15.9: a writer that never reads stalls itself, not mcemu or the other clients.
        with Mcemu() as m:
            pid = m.proc.pid

            def rss_kib():
                with open(f"/proc/{pid}/status") as f:
                    for line in f:
                        if line.startswith("VmRSS:"):
                            return int(line.split()[1])
                return 0

            fill_trace_ring(m.ports["refgo"])
            reader = Nc(m.ports["refgo"])
            reader.request("TP")
            rss0 = rss_kib()
            w = connect(m.ports["refgo"])
            w.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            w.setblocking(False)
            chunk = b"TP\r" * 1000
            end = time.monotonic() + 2.0
            sent = 0
            while time.monotonic() < end:
                try:
                    sent += w.send(chunk)
                except BlockingIOError:
                    pass
                t0 = time.monotonic()
                self.assertRegex(reader.request("TP", timeout=1.0), vector_regex(b"TP\r\n{TP}\r\n>"))
                self.assertLess(time.monotonic() - t0, 1.0)
            self.assertGreater(sent, 0)
            growth = rss_kib() - rss0
            if not SANITIZED:  # ASan keeps freed memory in quarantine: RSS says nothing about the queue there
                self.assertLess(growth, 1024, f"VmRSS grew {growth} KiB: the output queue must stay bounded (§2.6)")
            w.close()
            reader.close()
            # the slot is free again
            with Nc(m.ports["refgo"]) as again:
                self.assertRegex(again.request("TP"), vector_regex(b"TP\r\n{TP}\r\n>"))


if __name__ == "__main__":
    unittest.main()
