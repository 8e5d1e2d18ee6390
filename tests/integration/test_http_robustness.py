"""HTTP junk against the real mcemu binary (web.md §1.1, §1.2; README "bad input never crashes").

Each kind of junk — bytes that are not HTTP, a 100 KiB header, a huge Content-Length with a body
still being sent, a TLS ClientHello, slowloris connections that send a byte at a time — must get a
4xx status or a close, and meanwhile RefGo (port 10001 service), SLCAN and HTTP keep answering.
Python's standard library only; every wait is bounded and polls.
"""
import json
import os
import socket
import threading
import time
import unittest
import urllib.request

from mcemu_harness import Mcemu, wait_for

TLS_CLIENT_HELLO = (bytes.fromhex("160301 00c8 01 0000c4 0303") + os.urandom(32) +
                    bytes.fromhex("00 0004 1301 00ff 0100") + bytes(160))


def recv_until(sock, predicate, timeout=5.0):
    """Reads until predicate(data) or EOF/reset; returns (data, closed)."""
    data = b""
    deadline = time.monotonic() + timeout
    while not predicate(data):
        left = deadline - time.monotonic()
        if left <= 0:
            return data, False
        sock.settimeout(left)
        try:
            chunk = sock.recv(65536)
        except socket.timeout:
            continue
        except ConnectionResetError:
            return data, True
        if not chunk:
            return data, True
        data += chunk
    return data, False


def status_of(data):
    if not data.startswith(b"HTTP/1."):
        return None
    return int(data[9:12])


class Services:
    """Checks that RefGo, SLCAN and HTTP answer, each on a fresh connection."""

    def __init__(self, m):
        self.m = m

    def refgo(self):
        with socket.create_connection(("127.0.0.1", self.m.ports["refgo"]), timeout=5) as s:
            s.sendall(b"TP\r")
            data, _ = recv_until(s, lambda d: d.endswith(b">"))
            return data.startswith(b"TP\r\n") and data.endswith(b"\r\n>")

    def slcan(self):
        with socket.create_connection(("127.0.0.1", self.m.ports["slcan"]), timeout=5) as s:
            s.sendall(b"V\r")
            data, _ = recv_until(s, lambda d: d.endswith(b"\r"))
            return data == b"V1010\r"

    def http(self):
        with urllib.request.urlopen(f"http://127.0.0.1:{self.m.ports['http']}/api/v1/info", timeout=5) as r:
            return r.status == 200 and json.loads(r.read())["emulator"] == "mcemu"

    def all(self):
        return self.refgo() and self.slcan() and self.http()


class HttpJunk(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.m = Mcemu()
        cls.services = Services(cls.m)

    @classmethod
    def tearDownClass(cls):
        cls.m.__exit__(None, None, None)

    def setUp(self):
        self.assertTrue(self.services.all())

    def tearDown(self):
        self.assertIsNone(self.m.proc.poll(), "mcemu exited:\n" + self.m.log())
        self.assertTrue(self.services.all())

    def http_socket(self):
        return socket.create_connection(("127.0.0.1", self.m.ports["http"]), timeout=5)

    def exchange(self, payload):
        with self.http_socket() as s:
            s.sendall(payload)
            return recv_until(s, lambda d: b"\r\n\r\n" in d)

    def test_not_http_is_400(self):
        for junk in (b"HELLO WORLD\r\n\r\n", b"\x00\x01\x02\x03\xff\xfe\r\n\r\n", b"GET / HTTP/7.0\r\n\r\n"):
            data, _ = self.exchange(junk)
            self.assertEqual(status_of(data), 400, (junk, data))
            self.assertIn(b"Connection: close", data)

    def test_tls_client_hello_gets_4xx_or_close(self):
        data, closed = self.exchange(TLS_CLIENT_HELLO)
        status = status_of(data)
        self.assertTrue(closed or (status is not None and 400 <= status < 500), data)

    def test_100_kib_header_is_431(self):
        data, _ = self.exchange(b"GET /index.html HTTP/1.1\r\nHost: x\r\nX-Junk: " + b"a" * 100 * 1024 + b"\r\n\r\n")
        self.assertEqual(status_of(data), 431, data[:200])

    def test_huge_content_length_is_413_while_still_sending(self):
        with self.http_socket() as s:
            s.sendall(b"POST /api/v1/objects/read HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                      b"Content-Length: 100000000000\r\n\r\n")

            def keep_sending():
                block = b"{" * 65536
                try:
                    for _ in range(64):
                        s.sendall(block)
                except OSError:
                    pass  # the server closed after its 1 s of discarding: expected

            sender = threading.Thread(target=keep_sending)
            sender.start()
            data, _ = recv_until(s, lambda d: b"\r\n\r\n" in d)
            sender.join(timeout=30)
        self.assertEqual(status_of(data), 413, data[:200])
        self.assertIn(b"Connection: close", data)

    def test_slowloris_does_not_block_anyone(self):
        request = b"GET /api/v1/info HTTP/1.1\r\nHost: x\r\n\r\n"
        slow = [self.http_socket() for _ in range(8)]
        try:
            for i in range(len(request) - 4):
                for s in slow:
                    s.sendall(request[i:i + 1])
                if i % 8 == 0:
                    self.assertTrue(self.services.all(), f"services blocked after {i} bytes of slowloris")
            for s in slow:
                s.sendall(request[-4:])
            for s in slow:
                data, _ = recv_until(s, lambda d: b"\r\n\r\n" in d)
                self.assertEqual(status_of(data), 200)
        finally:
            for s in slow:
                s.close()

    def test_connection_limit_then_recovery(self):
        # 32 is the HTTP default (README); the 33rd is closed at once with one warning
        held = [self.http_socket() for _ in range(32)]
        try:
            extra = self.http_socket()
            data, closed = recv_until(extra, lambda d: False, timeout=5)
            extra.close()
            self.assertTrue(closed)
            self.assertEqual(data, b"")
            wait_for(lambda: self.m.has_line("http: connection limit 32 reached"), what="limit warning")
        finally:
            for s in held:
                s.close()
        # the 32 closes reach the server one by one: until the last is seen, a new connection can
        # still find the limit reached and be reset, which is the limit working, not a failure
        wait_for(lambda: self.http_or_reset(), what="HTTP after the connection limit")

    def http_or_reset(self):
        try:
            return self.services.http()
        except ConnectionError:
            return False

    def test_websocket_without_upgrade_is_426(self):
        data, _ = self.exchange(b"GET /api/v1/ws HTTP/1.1\r\nHost: x\r\n\r\n")
        self.assertEqual(status_of(data), 426)


if __name__ == "__main__":
    unittest.main()
