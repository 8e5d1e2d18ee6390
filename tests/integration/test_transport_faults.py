"""Transport fault injection (web.md §9, slcan-canopen.md §11.3) seen by real clients of the real
binary: netcat on RefGo, python-can's slcan interface (and a raw socket) on SLCAN, a UDP socket on
the debug port, HTTP. Each kind's observable effect, its count / durationMs, the trace events of
its injection, application and removal, and that the connection and the drive stay usable."""
import json
import socket
import time
import unittest

from mcemu_harness import Mcemu, wait_for
from nc_client import Nc
from slcan_client import Client, Raw, SdoAbort

NODE = 50
HEARTBEAT = 0x700 + NODE
SDO_TX = 0x580 + NODE


def post_fault(m, body):
    status, text = m.http("POST", "/api/v1/faults", body)
    assert status == 201, (status, text)
    return json.loads(text)["id"]


def active(m):
    return [f["id"] for f in json.loads(m.http("GET", "/api/v1/faults")[1])["faults"]]


def trace_texts(m, channels):
    events = json.loads(m.http("GET", f"/api/v1/trace?channels={channels}&limit=10000")[1])["events"]
    return [e["text"] for e in events]


def assert_traced(test, m, fid, kind, channel):
    """Injection and removal on channel api, each application on the kind's channel."""
    wait_for(lambda: fid not in active(m), what=f"{fid} removed")
    api = trace_texts(m, "api")
    test.assertTrue(any(t.startswith(f"fault {fid} added") for t in api), api)
    test.assertTrue(any(t.startswith(f"fault {fid} removed") for t in api), api)
    test.assertIn(f"fault {fid} {kind} applied", trace_texts(m, channel))


def silent_for(nc, seconds):
    """True if nothing arrives on `nc` for `seconds`."""
    try:
        nc.wait(lambda b: len(b) > 0, timeout=seconds)
        return False
    except TimeoutError:
        return True


class RefgoFaults(unittest.TestCase):
    def test_no_reply_swallows_the_next_replies_then_the_connection_answers(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            self.assertRegex(nc.request("TP"), rb"^TP\r\n-?\d+\r\n>$")
            fid = post_fault(m, {"kind": "refgo.noReply", "count": 2})
            nc.send(b"TS\rTPSR\r")
            self.assertTrue(silent_for(nc, 0.3), "replies were dropped")
            self.assertRegex(nc.request("TP"), rb"^TP\r\n-?\d+\r\n>$", "the third reply is sent")
            assert_traced(self, m, fid, "refgo.noReply", "refgo")
            self.assertTrue(any(t.startswith("reply not sent") and "TS\r\n" in t for t in trace_texts(m, "refgo")))

    def test_delay_holds_replies_back_in_order(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            fid = post_fault(m, {"kind": "refgo.delay", "ms": 400, "count": 1})
            t0 = time.monotonic()
            nc.send(b"TS\rTP\r")  # TS delayed; TP not delayed itself but must not overtake it
            replies = nc.replies(2, timeout=5)
            elapsed = time.monotonic() - t0
            self.assertGreaterEqual(elapsed, 0.38)
            self.assertTrue(replies[0].startswith(b"TS\r\n"), replies)
            self.assertTrue(replies[1].startswith(b"TP\r\n"), replies)
            assert_traced(self, m, fid, "refgo.delay", "refgo")
            t0 = time.monotonic()
            nc.request("TP")
            self.assertLess(time.monotonic() - t0, 0.35, "count 1: the next reply is not delayed")

    def test_duration_ends_the_injection_by_drive_time(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            fid = post_fault(m, {"kind": "refgo.noReply", "durationMs": 300})
            nc.send(b"TP\r")
            self.assertTrue(silent_for(nc, 0.1))
            wait_for(lambda: fid not in active(m), timeout=5, what="expiry")
            self.assertIn(f"fault {fid} removed (duration)", trace_texts(m, "api"))
            self.assertRegex(nc.request("TP"), rb"^TP\r\n-?\d+\r\n>$")

    def test_disconnect_closes_every_refgo_connection_and_nothing_else(self):
        # Plain sockets: netcat keeps running after the peer's close while its stdin is open.
        with Mcemu() as m:
            a, b = (socket.create_connection(("127.0.0.1", m.ports["refgo"]), timeout=5) for _ in range(2))
            raw = Raw(m.ports["slcan"])
            try:
                for s in (a, b):
                    s.sendall(b"TP\r")
                    self.assertTrue(s.recv(100).endswith(b">"))
                raw.exchange(b"V\r", b"V1010\r")
                fid = post_fault(m, {"kind": "refgo.disconnect"})
                for s in (a, b):
                    self.assertEqual(s.recv(100), b"", "closed by mcemu")
                self.assertEqual(raw.exchange(b"V\r", b"V1010\r"), b"V1010\r", "SLCAN stays connected")
                with Nc(m.ports["refgo"]) as c:
                    self.assertRegex(c.request("TP"), rb"^TP\r\n-?\d+\r\n>$", "new connections are served")
                assert_traced(self, m, fid, "refgo.disconnect", "refgo")
                wait_for(lambda: trace_texts(m, "refgo").count("disconnect") >= 2, what="disconnect events")
            finally:
                raw.close()
                a.close()
                b.close()


class UdpAndHttpFaults(unittest.TestCase):
    def test_udp_drop_drops_the_next_datagram(self):
        with Mcemu() as m:
            fid = post_fault(m, {"kind": "udp.drop", "count": 1})
            s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            s.settimeout(0.4)
            try:
                s.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
                with self.assertRaises(socket.timeout):
                    s.recvfrom(4096)  # the initial response (start-up block, "\r", ">") was dropped
                s.settimeout(5)
                s.sendto(b"\r", ("127.0.0.1", m.ports["udp"]))
                self.assertEqual(s.recvfrom(4096)[0], b"\r>\r\n", "registered; the backlog went with the drop")
            finally:
                s.close()
            udp = json.loads(m.http("GET", "/api/v1/udp")[1])
            self.assertEqual(udp["counters"]["datagramsDropped"], 1)
            assert_traced(self, m, fid, "udp.drop", "udp")

    def test_http_error_answers_the_next_page_request(self):
        with Mcemu() as m:
            fid = post_fault(m, {"kind": "http.error", "status": 503, "path": "/index", "count": 1})
            self.assertEqual(m.http("GET", "/api/v1/info")[0], 200, "not /api/")
            self.assertEqual(m.http("GET", "/static/none")[0], 404, "other paths do not match")
            self.assertEqual(m.http("GET", "/index.html")[0], 503)
            self.assertEqual(m.http("GET", "/index.html")[0], 200)
            assert_traced(self, m, fid, "http.error", "http")


class SlcanFaults(unittest.TestCase):
    def test_sdo_abort_at_initiate_then_the_node_answers(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                fid = post_fault(m, {"kind": "slcan.sdoAbort", "index": "6041h", "sub": 0, "code": "08000020h"})
                with self.assertRaises(SdoAbort) as e:
                    c.upload(0x6041, 0)
                self.assertEqual(e.exception.code, 0x08000020)
                self.assertEqual(len(c.upload(0x6041, 0)), 2, "the next transfer is answered")
                assert_traced(self, m, fid, "slcan.sdoAbort", "slcan")
            finally:
                c.close()

    def test_sdo_abort_at_end_of_a_download_leaves_the_object_alone(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                before = c.upload(0x607A, 0)
                post_fault(m, {"kind": "slcan.sdoAbort", "index": "607Ah", "sub": 0, "code": "06090030h",
                               "phase": "end"})
                with self.assertRaises(SdoAbort) as e:
                    c.download(0x607A, 0, (12345).to_bytes(4, "little"))
                self.assertEqual(e.exception.code, 0x06090030)
                self.assertEqual(c.upload(0x607A, 0), before, "the OD was not touched")
            finally:
                c.close()

    def test_sdo_no_reply_swallows_one_response_and_the_node_stays_usable(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                fid = post_fault(m, {"kind": "slcan.sdoNoReply", "index": "6041h", "count": 1})
                with self.assertRaises(TimeoutError):
                    c.sdo(bytes([0x40, 0x41, 0x60, 0x00]), timeout=0.4)
                self.assertEqual(len(c.upload(0x1000, 0)), 4)
                self.assertEqual(len(c.upload(0x6041, 0)), 2)
                assert_traced(self, m, fid, "slcan.sdoNoReply", "slcan")
            finally:
                c.close()

    def test_drop_tx_by_identifier(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                fid = post_fault(m, {"kind": "slcan.dropTx", "cobId": f"{SDO_TX:X}h", "count": 1})
                with self.assertRaises(TimeoutError):
                    c.sdo(bytes([0x40, 0x41, 0x60, 0x00]), timeout=0.4)
                self.assertEqual(len(c.upload(0x6041, 0)), 2)
                assert_traced(self, m, fid, "slcan.dropTx", "slcan")
            finally:
                c.close()

    def test_delay_tx_holds_node_frames_back(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                fid = post_fault(m, {"kind": "slcan.delayTx", "ms": 400, "count": 1})
                t0 = time.monotonic()
                c.upload(0x6041, 0)
                self.assertGreaterEqual(time.monotonic() - t0, 0.38)
                t0 = time.monotonic()
                c.upload(0x6041, 0)
                self.assertLess(time.monotonic() - t0, 0.35)
                assert_traced(self, m, fid, "slcan.delayTx", "slcan")
            finally:
                c.close()

    def test_heartbeat_stop_suspends_heartbeats_until_removed(self):
        with Mcemu() as m:
            c = Client(m.ports["slcan"])
            try:
                c.download(0x1017, 0, (50).to_bytes(2, "little"))
                self.assertIsNotNone(c.recv_until(lambda f: f.arbitration_id == HEARTBEAT, timeout=2))
                fid = post_fault(m, {"kind": "slcan.heartbeatStop"})
                c.collect(0.1)  # a heartbeat already on its way
                self.assertEqual(c.collect(0.5, lambda f: f.arbitration_id == HEARTBEAT), [])
                self.assertEqual(m.http("DELETE", f"/api/v1/faults/{fid}")[0], 200)
                self.assertIsNotNone(c.recv_until(lambda f: f.arbitration_id == HEARTBEAT, timeout=2))
                self.assertIn(f"fault {fid} slcan.heartbeatStop applied", trace_texts(m, "slcan"))
            finally:
                c.close()

    def test_bel_raw_tx_and_disconnect(self):
        with Mcemu() as m, Nc(m.ports["refgo"]) as nc:
            a, b = Raw(m.ports["slcan"]), Raw(m.ports["slcan"])
            try:
                fid = post_fault(m, {"kind": "slcan.bel", "count": 1})
                self.assertEqual(a.exchange(b"V\r", b"\a"), b"\a")
                self.assertEqual(a.exchange(b"V\r", b"V1010\r"), b"V1010\r")
                assert_traced(self, m, fid, "slcan.bel", "slcan")
                fid = post_fault(m, {"kind": "slcan.rawTx", "text": "t7321\r"})
                for s in (a, b):
                    self.assertEqual(s.read_until(lambda buf: buf.endswith(b"t7321\r")), b"t7321\r")
                assert_traced(self, m, fid, "slcan.rawTx", "slcan")
                fid = post_fault(m, {"kind": "slcan.disconnect"})
                for s in (a, b):
                    s.sock.settimeout(5)
                    self.assertEqual(s.sock.recv(100), b"", "closed by mcemu")
                self.assertRegex(nc.request("TP"), rb"^TP\r\n-?\d+\r\n>$", "RefGo stays connected")
                c = Raw(m.ports["slcan"])
                self.assertEqual(c.exchange(b"V\r", b"V1010\r"), b"V1010\r", "new SLCAN sessions are served")
                c.close()
                assert_traced(self, m, fid, "slcan.disconnect", "slcan")
            finally:
                a.close()
                b.close()


if __name__ == "__main__":
    unittest.main()
