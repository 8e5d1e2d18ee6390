"""Peers that vanish without a FIN (issue 12, refgo.md §1.3, slcan-canopen.md §3.1): eight RefGo and
eight SLCAN clients fill the default limit of 8, then every packet of theirs is dropped, as when a
PLC loses power or a cable is pulled. mcemu's keepalive (10 s idle, 3 probes 5 s apart) and
TCP_USER_TIMEOUT (25 s) must free the slots, so that a ninth client is served within about 25 s.

The drop needs a network of the test's own: the test re-runs this file inside a new network
namespace (`unshare --net`, root) with its own loopback, where an nftables rule drops the sixteen
clients' packets; nothing outside the namespace is touched. Without root, unshare or nft the test
is skipped, naming what is missing. The SLCAN node sends a heartbeat every 100 ms, so on that port
output is pending and the user timeout (not keepalive) is what frees the slot.
"""
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
KEEPALIVE_WINDOW_S = 10 + 3 * 5  # TCP_KEEPIDLE + TCP_KEEPCNT × TCP_KEEPINTVL = TCP_USER_TIMEOUT 25 s
SKIP_EXIT = 77


def skip_reason():
    if os.geteuid() != 0:
        return "needs root for a network namespace (unshare --net) and an nftables rule"
    for tool in ("unshare", "nft", "ip"):
        if not shutil.which(tool):
            return f"needs {tool} (packages util-linux, nftables, iproute2)"
    return None


class VanishedPeers(unittest.TestCase):
    @unittest.skipIf(skip_reason(), skip_reason() or "")
    def test_eight_vanished_peers_free_their_slots_within_the_keepalive_window(self):
        r = subprocess.run(["unshare", "--net", sys.executable, os.path.abspath(__file__), "--in-netns"],
                           capture_output=True, text=True, timeout=240, env=dict(os.environ))
        if r.returncode == SKIP_EXIT:
            self.skipTest(r.stdout.strip().splitlines()[-1] if r.stdout.strip() else "namespace set-up failed")
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr[-4000:]}")
        result = json.loads(r.stdout.strip().splitlines()[-1])
        print(f"\nvanished peers: {json.dumps(result)}", file=sys.stderr)
        for service in ("refgo", "slcan"):
            self.assertTrue(result[f"{service}_refused_while_full"], service)
            served = result[f"{service}_served_after_s"]
            self.assertIsNotNone(served, f"{service}: no ninth client served within the wait")
            # the slot is freed by the peer timeout, so it takes about the keepalive window, not less
            self.assertGreater(served, KEEPALIVE_WINDOW_S - 10, service)
            self.assertLess(served, KEEPALIVE_WINDOW_S + 15, service)
        self.assertGreaterEqual(result["timed_out_lines"], 16, "every vanished peer ends as a timed-out disconnect")


def served(port, request, reply, timeout=5.0):
    """True if a new connection gets `reply` to `request`; False if mcemu closes it at once (full)."""
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    except OSError:
        return False
    try:
        s.sendall(request)
        got = b""
        while not got.endswith(reply):
            chunk = s.recv(4096)
            if not chunk:
                return False
            got += chunk
        return True
    except OSError:
        return False
    finally:
        s.close()


def in_netns():
    """The scenario, run inside the private network namespace; prints one JSON line."""
    sys.path.insert(0, HERE)
    from mcemu_harness import Mcemu  # noqa: E402 - imported here: the harness reads MCEMU_BIN

    if subprocess.run(["ip", "link", "set", "lo", "up"]).returncode != 0:
        print("cannot bring up the namespace's loopback")
        sys.exit(SKIP_EXIT)
    cfg = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"mcemu-vanish-{os.getpid()}.json")
    with open(cfg, "w") as f:
        json.dump({"objects": {"1017.00": 100}}, f)  # heartbeat: output pending on every SLCAN link
    result = {}
    try:
        with Mcemu("--config", cfg, "--log-level", "debug") as m:
            ports = {"refgo": m.ports["refgo"], "slcan": m.ports["slcan"]}
            probe = {"refgo": (b"TS\r", b">"), "slcan": (b"V\r", b"V1010\r")}
            peers = []
            for service, port in ports.items():
                for _ in range(8):
                    s = socket.create_connection(("127.0.0.1", port), timeout=5)
                    s.sendall(probe[service][0])
                    got = b""
                    while not got.endswith(probe[service][1]) and probe[service][1] not in got:
                        chunk = s.recv(4096)
                        assert chunk, f"{service}: peer closed during set-up"
                        got += chunk
                    peers.append(s)
                result[f"{service}_refused_while_full"] = not served(port, *probe[service])
            client_ports = ",".join(str(s.getsockname()[1]) for s in peers)
            rules = ["add table inet vanish",
                     "add chain inet vanish out { type filter hook output priority 0 ; }",
                     f"add rule inet vanish out tcp sport {{ {client_ports} }} drop",
                     f"add rule inet vanish out tcp dport {{ {client_ports} }} drop"]
            for rule in rules:
                r = subprocess.run(["nft"] + rule.split(), capture_output=True, text=True)
                if r.returncode != 0:
                    print(f"nft cannot drop packets here: {r.stderr.strip()}")
                    sys.exit(SKIP_EXIT)
            t0 = time.monotonic()
            pending = set(ports)
            for service in ports:
                result[f"{service}_served_after_s"] = None
            while pending and time.monotonic() - t0 < KEEPALIVE_WINDOW_S + 60:
                for service in sorted(pending):
                    if served(ports[service], *probe[service]):
                        result[f"{service}_served_after_s"] = round(time.monotonic() - t0, 1)
                        pending.discard(service)
                time.sleep(0.5)  # the poll interval of a client retrying its connection
            result["timed_out_lines"] = m.count_lines("Connection timed out")
            for s in peers:
                s.close()
    finally:
        os.unlink(cfg)
    print(json.dumps(result))


if __name__ == "__main__":
    if sys.argv[1:] == ["--in-netns"]:
        in_netns()
    else:
        unittest.main()
