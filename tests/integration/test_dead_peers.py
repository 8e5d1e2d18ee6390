"""Slow and silent peers (issue 12): --idle-timeout, and a RefGo client that never reads its replies.

What "dropped" means for a RefGo client that never reads (README "Hardening"): refgo.md §2.6 keeps
it connected — mcemu stops reading from it once 256 KiB of replies are queued, so its own sends
stall and it costs bounded memory — and TCP_USER_TIMEOUT (§1.3, 25 s) then ends the connection in
the kernel once the peer's receive window has stayed zero that long. The slot is free again, and
the other clients never notice. (An SLCAN client is closed at once when its queue is full, §3.1.)
"""
import socket
import time
import unittest

from mcemu_harness import Mcemu, connect, fill_trace_ring
from nc_client import vector_regex


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def closed_without_a_byte(s, timeout=60.0):
    """Waits until mcemu closes `s`; True if it sent nothing before."""
    s.settimeout(timeout)
    try:
        return s.recv(100) == b""
    except ConnectionResetError:
        return True


class IdleTimeout(unittest.TestCase):
    def test_silent_connections_are_closed_after_the_timeout_and_talking_ones_are_not(self):
        with Mcemu("--idle-timeout", "2") as m:
            t0 = time.monotonic()
            silent_refgo = connect(m.ports["refgo"])
            silent_slcan = connect(m.ports["slcan"])
            talker = connect(m.ports["refgo"])
            talker.settimeout(10)
            # the talker sends a line every 0.1 s for 3 s (longer than the timeout) and stays served
            while time.monotonic() - t0 < 3.0:
                talker.sendall(b"TS\r")
                got = b""
                while not got.endswith(b">"):
                    chunk = talker.recv(100)
                    self.assertTrue(chunk, "the talking client was closed")
                    got += chunk
                self.assertEqual(got, b"TS\r\n0\r\n>")
                time.sleep(0.1)
            self.assertTrue(closed_without_a_byte(silent_refgo))
            self.assertTrue(closed_without_a_byte(silent_slcan))
            silent_refgo.close()
            silent_slcan.close()
            self.assertGreaterEqual(time.monotonic() - t0, 1.9, "closed before the timeout")
            talker.sendall(b"TS\r")
            self.assertEqual(talker.recv(100), b"TS\r\n0\r\n>")
            talker.close()
            self.assertEqual(m.count_lines("(--idle-timeout)"), 2)


class NeverReadingClient(unittest.TestCase):
    def test_a_client_that_never_reads_is_dropped_by_the_user_timeout_and_frees_its_slot(self):
        with Mcemu("--max-clients", "2") as m:
            fill_trace_ring(m.ports["refgo"])
            reader = connect(m.ports["refgo"])
            reader.settimeout(10)
            flooder = connect(m.ports["refgo"])
            flooder.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
            flooder.setblocking(False)
            rss0 = rss_kib(m.proc.pid)

            def ask(s):
                s.sendall(b"TP\r")
                got = b""
                while not got.endswith(b">"):
                    chunk = s.recv(4096)
                    self.assertTrue(chunk)
                    got += chunk
                return got

            t0 = time.monotonic()
            sent = 0
            dropped_after = None
            peak_rss = rss0
            while time.monotonic() - t0 < 60:
                try:
                    sent += flooder.send(b"TP\r" * 1000)
                except BlockingIOError:
                    pass  # mcemu stopped reading: the flooder's own sends stall (§2.6)
                except (ConnectionResetError, BrokenPipeError):
                    pass  # mcemu's side is gone
                self.assertRegex(ask(reader), vector_regex(b"TP\r\n{TP}\r\n>"))  # the other client is served
                peak_rss = max(peak_rss, rss_kib(m.proc.pid))
                probe = connect(m.ports["refgo"])  # a third client: refused while the flooder holds its slot
                probe.settimeout(10)
                try:
                    probe.sendall(b"TS\r")
                    if probe.recv(100) == b"TS\r\n0\r\n>":
                        dropped_after = time.monotonic() - t0
                        break
                except (ConnectionResetError, BrokenPipeError):
                    pass
                finally:
                    probe.close()
                time.sleep(0.5)
            self.assertGreater(sent, 0)
            self.assertIsNotNone(dropped_after, "the never-reading client still holds its slot after 60 s")
            self.assertGreater(dropped_after, 15, "dropped by the 25 s user timeout, not before")
            self.assertLess((peak_rss - rss0), 2048, f"VmRSS grew {peak_rss - rss0} KiB: the queue is bounded")
            self.assertTrue(m.has_line("refgo") and m.proc.poll() is None)
            print(f"\nnever-reading client: {sent} bytes sent before its sends stalled, dropped after "
                  f"{dropped_after:.1f} s, VmRSS {rss0} → peak {peak_rss} KiB", flush=True)
            reader.close()
            flooder.close()


if __name__ == "__main__":
    unittest.main()
