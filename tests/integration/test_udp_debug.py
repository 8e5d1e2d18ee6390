"""UDP debug console of the real mcemu binary (udp-debug.md §1–§5, vectors of §7).

Listeners are Python UDP sockets (as Docklight or Fullmo's UdpMonitor) and `nc -u` (as a shell
user). Waiting for a datagram is bounded by a receive timeout; the absence of a datagram is checked
with a short timeout, which is the only way to observe it.
"""
import json
import os
import socket
import tempfile
import time
import unittest

from mcemu_harness import Mcemu
from nc_client import Nc

BOOT = (b"SYS_Initialize: The MPFS2 File System is mounted\r\n"
        b"TCP/IP Stack: Initialization Ended - success \n\r"
        b"Host MOVINGCAP TCP   - NBNS disabled\r\n"
        b"IP Address: %s \r\n"
        b"REFGO - opening server\r\n"
        b"code: starting upload...\r\n"
        b"code: upload complete, script id: (empty)\r\n")


def listener(bind="127.0.0.1", port=0, reuse=False):
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    if reuse:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    s.bind((bind, port))
    s.settimeout(5)
    return s


def recv(s, timeout=5.0):
    s.settimeout(timeout)
    return s.recvfrom(4096)


def nothing_within(s, seconds=0.3):
    s.settimeout(seconds)
    try:
        data = s.recvfrom(4096)
    except socket.timeout:
        return True
    raise AssertionError(f"unexpected datagram {data!r}")


def config_file(doc):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(doc, f)
    f.close()
    return f.name


class Registration(unittest.TestCase):
    def test_first_registration_gets_the_boot_log_then_only_the_prompt(self):
        with Mcemu("--ip", "10.1.2.3") as m:
            udp_port = m.ports["udp"]
            s = listener()
            s.sendto(b"\r", ("127.0.0.1", udp_port))
            data, src = recv(s)
            self.assertEqual(data, BOOT % b"10.1.2.3" + b"\r>\r\n")
            self.assertEqual(src, ("127.0.0.1", udp_port), "answers come from --udp-port")
            s.sendto(b"\r", ("127.0.0.1", udp_port))
            self.assertEqual(recv(s)[0], b"\r>\r\n")
            nothing_within(s)
            # a later registration from another port gets only its own echo and the prompt
            t = listener()
            t.sendto(b"\r\n", ("127.0.0.1", udp_port))
            self.assertEqual(recv(t)[0], b"\r\n>\r\n")
            s.close()
            t.close()

    def test_other_payloads_are_ignored(self):
        with Mcemu() as m:
            s = listener()
            for payload in (b"hello", b"TP\r", b"\r\r\r\r\r", b" \r"):
                s.sendto(payload, ("127.0.0.1", m.ports["udp"]))
            nothing_within(s)
            s.sendto(b"\n", ("127.0.0.1", m.ports["udp"]))
            self.assertEqual(recv(s)[0], BOOT % b"192.168.2.150" + b"\n>\r\n", "the backlog was kept")
            s.close()

    def test_nc_u_registers_with_enter(self):
        # `nc -u 127.0.0.1 <port>` and Enter: an LF-only datagram registers (udp-debug.md §10).
        with Mcemu() as m, Nc(m.ports["udp"], udp=True) as nc:
            nc.send(b"\n")
            expected = BOOT % b"192.168.2.150" + b"\n>\r\n"
            got = nc.wait(lambda b: len(b) >= len(expected), timeout=5, what="boot log")
            self.assertEqual(got, expected)


class StatusLines(unittest.TestCase):
    def test_notes_report_refgo_clients_and_faults(self):
        cfg = config_file({"settings": {"udpEmulatorNotes": True}, "plant": {"supply_nominal_V": 10}})
        try:
            with Mcemu("--config", cfg) as m:
                s = listener()
                s.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
                # the start-up block first; the under-voltage fault of power-up follows, before or after
                # the registration (depending on whether it was detected yet)
                fault = b"mcemu: fault 3221h ERROR_UNDER_VOLT\r\n"
                data = b""
                while fault not in data:
                    data += recv(s)[0]
                boot = BOOT % b"192.168.2.150"
                self.assertIn(data, (boot + fault + b"\r>\r\n", boot + b"\r>\r\n" + fault))
                r = socket.create_connection(("127.0.0.1", m.ports["refgo"]))
                local = "%s:%d" % r.getsockname()
                self.assertEqual(recv(s)[0], f"mcemu: refgo client {local} connected\r\n".encode())
                r.close()
                self.assertEqual(recv(s)[0], f"mcemu: refgo client {local} disconnected\r\n".encode())
                s.close()
        finally:
            os.unlink(cfg)

    def test_notes_are_off_by_default(self):
        with Mcemu() as m:
            s = listener()
            s.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
            recv(s)
            socket.create_connection(("127.0.0.1", m.ports["refgo"])).close()
            nothing_within(s)
            s.close()


class Listeners(unittest.TestCase):
    def test_four_listeners_fifth_evicts_the_oldest_registration(self):
        cfg = config_file({"settings": {"udpEmulatorNotes": True}})
        try:
            with Mcemu("--config", cfg) as m:
                port = m.ports["udp"]
                socks = [listener() for _ in range(5)]
                for s in socks[:4]:
                    s.sendto(b"\r", ("127.0.0.1", port))
                    recv(s)
                socket.create_connection(("127.0.0.1", m.ports["refgo"])).close()
                for s in socks[:4]:
                    data, src = recv(s)
                    self.assertIn(b"connected", data)
                    self.assertEqual(src[1], port)
                    self.assertIn(b"disconnected", data if b"disconnected" in data else recv(s)[0])
                socks[0].sendto(b"\r", ("127.0.0.1", port))  # the first re-registers: now the newest
                self.assertEqual(recv(socks[0])[0], b"\r>\r\n")
                socks[4].sendto(b"\r", ("127.0.0.1", port))  # evicts the second
                self.assertEqual(recv(socks[4])[0], b"\r>\r\n")
                socket.create_connection(("127.0.0.1", m.ports["refgo"])).close()
                for i in (0, 2, 3, 4):
                    self.assertIn(b"mcemu: refgo client", recv(socks[i])[0])
                nothing_within(socks[1])
                for s in socks:
                    s.close()
        finally:
            os.unlink(cfg)

    def test_udpk_pattern_on_a_shared_port(self):
        # §7.7: the host tool binds 0.0.0.0:P with SO_REUSEADDR and talks to mcemu bound to 127.0.0.2:P.
        probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        probe.bind(("127.0.0.1", 0))
        p = probe.getsockname()[1]
        probe.close()
        with Mcemu("--bind", "127.0.0.2", "--refgo-port", "0", "--slcan-port", "0", "--http-port", "0",
                   "--udp-port", str(p), ports_zero=False) as m:
            self.assertEqual(m.ports["udp"], p)
            s = listener("0.0.0.0", p, reuse=True)
            s.sendto(b"\r", ("127.0.0.2", p))
            lines = []
            deadline = time.monotonic() + 5
            while not any(b"REFGO - opening server" in d for d in lines):
                self.assertLess(time.monotonic(), deadline)
                data, src = recv(s)
                if src[0] == "127.0.0.2":
                    lines.append(data)
            self.assertEqual(src, ("127.0.0.2", p))
            s.close()


if __name__ == "__main__":
    unittest.main()
