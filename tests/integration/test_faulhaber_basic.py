"""MC BASIC on the FAULHABER drive (faulhaber.md §9–§11, issue 25) against the real binary.

AN165's Examples A and B run under --clock manual from the fixture files: uploaded over HTTP,
started, the clock advanced in small slices, an observer on the binary protocol reading objects and
recording statusword notifications, and the `basic` trace channel giving every SETOBJ with its drive
time. Every pass criterion of faulhaber.md §10 is checked. Then: SAVE/LOAD and programs across a
restart, autostart after a power cycle and a reset node telegram, programs that loop forever, divide
by zero or recurse without end, and 0x3005 written over the binary protocol.
"""
import http.client
import json
import os
import re
import tempfile
import time
import unittest

import faulhaber_client as fc
from mcemu_harness import Mcemu, wait_for

HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "..", "scripting", "basic", "fixtures")
FH = ("--model", "FH_MC5005")
SETOBJ_RE = re.compile(r"^setobj line (\d+) ([0-9A-F]{4})h\.([0-9A-F]{2}) = (-?\d+)$")
VAR = {chr(ord("a") + i): i + 1 for i in range(26)}  # variable → sub-index of 0x3005
VMAX_INC_PER_MS = 70  # 6081h = 1000 min⁻¹ = 68.3 inc/ms; homing 6099h.01 = 400 min⁻¹ is slower


def fixture(name):
    with open(os.path.join(FIXTURES, name), "rb") as f:
        return f.read()


def config_file(doc):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(doc, f)
    f.close()
    return f.name


class Http:
    """One keep-alive HTTP connection (thousands of clock advances per test)."""

    def __init__(self, port, host="127.0.0.1"):
        self.host, self.port = host, port
        self.conn = http.client.HTTPConnection(host, port, timeout=120)

    def request(self, method, path, body=None, content_type="application/json"):
        data = None if body is None else (body if isinstance(body, bytes) else json.dumps(body).encode())
        headers = {"Content-Type": content_type} if data is not None else {}
        for attempt in (1, 2):
            try:
                self.conn.request(method, path, body=data, headers=headers)
                resp = self.conn.getresponse()
                return resp.status, resp.read()
            except (http.client.HTTPException, ConnectionError):
                if attempt == 2:
                    raise
                self.conn.close()
                self.conn = http.client.HTTPConnection(self.host, self.port, timeout=120)

    def json(self, method, path, body=None, expect=200, content_type="application/json"):
        status, data = self.request(method, path, body, content_type)
        if status != expect:
            raise AssertionError(f"{method} {path}: HTTP {status} {data[:300]!r}")
        return json.loads(data) if data else None

    def close(self):
        self.conn.close()


class Observer:
    """Advances the manual clock and watches the drive over the binary protocol.

    After every slice it reads 6041h, 6064h, 607Ah, 6067h and 6068h in one pipelined burst; the
    statusword notifications that arrived before those answers were sent during the slice and are
    recorded with the slice's end time (exact when the slice is 1 ms). `setobj()` fetches the SETOBJ
    events of the `basic` trace channel with their drive time.
    """

    OBJECTS = ((0x6041, 0, False), (0x6064, 0, True), (0x607A, 0, True), (0x6067, 0, False), (0x6068, 0, False))

    def __init__(self, m):
        self.m = m
        self.http = Http(m.ports["http"])
        self.client = fc.open_tcp(m.ports["faulhaber"], timeout=10)
        self.t = self.http.json("GET", "/api/v1/clock")["timeMs"]
        self.samples = []  # dicts: t, sw, pos, target, window, wtime
        self.notes = []  # (t, statusword) of every notification
        self.setobjs = []  # (t, line, index, sub, value)
        self.trace_since = self._trace_end()
        self.sample()

    def close(self):
        self.client.close()
        self.http.close()

    def _trace_end(self):
        since = 0
        while True:
            body = self.http.json("GET", f"/api/v1/trace?channels=basic&since={since}&limit=10000")
            if not body["events"]:
                return since
            since = body["nextSeq"]

    def read_many(self, objects):
        """Pipelined SDO reads: every request in one write, the answers in order."""
        c = self.client
        c.send(b"".join(fc.sdo_read_frame(1, i, s) for i, s, _ in objects))
        values = []
        for index, sub, signed in objects:
            while True:
                f = c.read_frame()
                if f is None:
                    raise TimeoutError(f"no answer for {index:04X}.{sub:02X}")
                if f.command in fc.ASYNC_COMMANDS:
                    if f.command == fc.STATUSWORD:
                        self.notes.append((self.t, f.statusword))
                    c.notifications.append(f)
                    continue
                if f.command != fc.SDO_READ or (f.index, f.sub) != (index, sub):
                    raise AssertionError(f"unexpected answer {f!r} for {index:04X}.{sub:02X}")
                values.append(int.from_bytes(f.value, "little", signed=signed))
                break
        return values

    def read(self, index, sub=0, signed=True):
        return self.read_many([(index, sub, signed)])[0]

    def var(self, name):
        return self.read(0x3005, VAR[name])

    def sample(self):
        sw, pos, target, window, wtime = self.read_many(self.OBJECTS)
        s = {"t": self.t, "sw": sw, "pos": pos, "target": target, "window": window, "wtime": wtime}
        self.samples.append(s)
        return s

    def advance(self, ms):
        self.t = self.http.json("POST", "/api/v1/clock/advance", {"ms": ms})["timeMs"]
        return self.sample()

    def setobj(self):
        """New SETOBJ events since the last call, appended to self.setobjs; returns them."""
        new = []
        while True:
            body = self.http.json("GET", f"/api/v1/trace?channels=basic&since={self.trace_since}&limit=10000")
            if body["dropped"]:
                raise AssertionError(f"{body['dropped']} basic trace events left the ring unread")
            for e in body["events"]:
                m = SETOBJ_RE.match(e["text"])
                if m:
                    new.append((e["timeMs"], int(m.group(1)), int(m.group(2), 16), int(m.group(3), 16),
                                int(m.group(4))))
                elif e["text"].startswith("error"):
                    raise AssertionError("program error: " + e["text"])
            if not body["events"]:
                break
            self.trace_since = body["nextSeq"]
        self.setobjs.extend(new)
        return new

    def set_inputs(self, levels):
        self.http.json("PUT", "/api/v1/faulhaber/inputs", {"levels": levels})

    def next_slice(self, s, extra_far=None):
        """1 ms unless the axis is travelling and still far from its target (and from `extra_far`,
        a position the test must not step over)."""
        if s["sw"] & 0x0400:
            return 1
        room = abs(s["pos"] - s["target"]) - s["window"] - 3 * VMAX_INC_PER_MS
        if extra_far is not None:
            room = min(room, abs(s["pos"] - extra_far) - 3 * VMAX_INC_PER_MS)
        return max(1, min(50, room // VMAX_INC_PER_MS))


def start_program(o, slot, text):
    state = o.http.json("PUT", f"/api/v1/faulhaber/programs/{slot}", text, content_type="text/plain")
    assert state["state"] == "loaded", state
    state = o.http.json("POST", f"/api/v1/faulhaber/programs/{slot}/start", {})
    assert state["state"] == "running", state


def writes(setobjs):
    return [(i, v) for _, _, i, _, v in setobjs]


def edge_in_slice(o, prev, cur):
    """Bit 10 rose in the slice that ended at `cur`: it was clear at `prev` and a notification of
    the slice has it set (it may drop again in the same step: the program's next 0x1F write)."""
    return not prev["sw"] & 0x0400 and any(t == cur["t"] and sw & 0x0400 for t, sw in o.notes)


def move_ends(o, after_t):
    """The (previous sample, edge sample) pairs of the rising edges of bit 10 after `after_t`."""
    out = []
    for k in range(1, len(o.samples)):
        prev, cur = o.samples[k - 1], o.samples[k]
        if cur["t"] > after_t and edge_in_slice(o, prev, cur):
            out.append((k, prev, cur))
    return out


def check_move_ends(test, o, setpoint_times):
    """faulhaber.md §10 A.4 / B.4: every rising edge of bit 10 (after the first set-point) happens
    with |6064h − 607Ah| ≤ 6067h, after the position has been inside the window for at least the
    current 6068h. The finished move's 607Ah, 6067h and 6068h are those of the sample before the
    edge (the program writes the next set-point in the same step). The window time counts from the
    later of: the last sample outside the window, the move's 0x1F write. Returns the edge count."""
    ends = move_ends(o, setpoint_times[0])
    for k, prev, cur in ends:
        test.assertEqual(cur["t"] - prev["t"], 1, f"edges are observed in 1 ms slices: {o.samples[k - 2:k + 1]}")
        target, window, wtime = prev["target"], prev["window"], prev["wtime"]
        test.assertLessEqual(abs(cur["pos"] - target), window, f"edge at {cur['t']} ms: {cur} after {prev}")
        started = max(t for t in setpoint_times if t < cur["t"])
        last_out = max([s["t"] for s in o.samples[:k] if abs(s["pos"] - target) > window] + [started])
        last_out = max(last_out, started)
        test.assertGreaterEqual(cur["t"] - last_out, wtime,
                                f"edge at {cur['t']} ms: inside {target}±{window} only since {last_out} ms")
    return len(ends)


class ExampleA(unittest.TestCase):
    """AN165 Example A (switch between two absolute positions), faulhaber.md §10 A.1–A.6, with the
    negative limit switch on DigIn3 driven by the test: high while the observed 6064h is ≤ −20000
    (before homing that is the plant's frame; after it the moves between ±10000 never reach it)."""

    SWITCH = -20000
    DIGIN1, DIGIN2, DIGIN3 = 0x01, 0x02, 0x04

    def test_example_a(self):
        with Mcemu(*FH, "--clock", "manual") as m:
            o = Observer(m)
            try:
                self.run_example(o)
            finally:
                o.close()

    def levels(self, s, *inputs):
        return sum(inputs) | (self.DIGIN3 if s["pos"] <= self.SWITCH else 0)

    def run_example(self, o):
        t0 = o.t
        start_program(o, 1, fixture("example_a.bas"))
        # A.1: 2310h.01 = 4, .02 = 0, .10 = 0, .11 = 0, 6083h = 6084h = 10, 6060h = 6, 6040h = 0;
        # Switch on disabled; y = 1
        init = [(0x2310, 4), (0x2310, 0), (0x2310, 0), (0x2310, 0), (0x6083, 10), (0x6084, 10), (0x6060, 6),
                (0x6040, 0)]
        s = o.samples[-1]
        while len(o.setobjs) < len(init) or o.var("y") != 1:
            self.assertLess(o.t - t0, 100, o.setobjs)
            s = o.advance(1)
            o.setobj()
        self.assertEqual(writes(o.setobjs), init)
        self.assertEqual([sub for _, _, _, sub, _ in o.setobjs[:4]], [0x01, 0x02, 0x10, 0x11])
        self.assertEqual(s["sw"] & 0x6F, 0x40)
        self.assertEqual(o.read(0x6061), 6)
        # nothing happens while DigIn1 is low
        s = o.advance(200)
        self.assertEqual(o.setobj(), [])
        self.assertEqual((s["sw"] & 0x6F, o.var("y")), (0x40, 1))

        # A.2: DigIn1 high → within 10 ms 0x06 then 0x0F, Operation enabled, y = 3
        inputs = (self.DIGIN1,)
        o.set_inputs(self.levels(s, *inputs))
        t_in = o.t
        while not (o.var("y") == 3 and s["sw"] & 0x6F == 0x27):
            self.assertLess(o.t - t_in, 10, "not enabled within 10 ms")
            s = o.advance(1)
        enable = o.setobj()
        self.assertEqual(writes(enable[:4]), [(0x6040, 0x06), (0x6040, 0x0F), (0x6098, 17), (0x6040, 0x1F)])
        self.assertTrue(all(t <= t_in + 10 for t, *_ in enable[:2]))

        # A.3: homing method 17 (6098h = 17, 0x1F): the axis moves negative to the switch, homing
        # completes (bits 12 and 10), then 6060h = 1 and z = 2
        lowest = 0
        homed = None
        while True:
            self.assertLess(o.t - t0, 60000, "homing did not complete")
            # towards the switch in slices that cannot pass it; from there on every ms (the switch
            # edge, the reference, the change to PP)
            room = abs(s["pos"] - self.SWITCH) - 3 * VMAX_INC_PER_MS
            s = o.advance(1 if lowest <= self.SWITCH else max(1, min(50, room // VMAX_INC_PER_MS)))
            lowest = min(lowest, s["pos"])
            levels = self.levels(s, *inputs)
            if levels != self.levels(o.samples[-2], *inputs):
                o.set_inputs(levels)
            if homed is None and any(t == s["t"] and sw & 0x1400 == 0x1400 for t, sw in o.notes):
                homed = s["t"]
            if homed is not None and (0x6060, 1) in writes(o.setobj()):
                break
        self.assertLessEqual(lowest, self.SWITCH, "the axis went onto the switch")
        self.assertEqual(o.read(0x6061), 1)
        homing = writes(o.setobjs[len(init) + 2:])
        self.assertEqual(homing[:4], [(0x6098, 17), (0x6040, 0x1F), (0x6040, 0x0F), (0x6060, 1)])
        self.assertLessEqual(abs(s["pos"]), 100, "the switch edge is the new 0")

        # A.4–A.5: profile position between +10000 and −10000 with the ramp r: until r has climbed to
        # 500, come down to 10 and turned up again (99 moves), or 600 s
        moves = []  # edge times
        r_sequence = []
        while len(r_sequence) < 99:
            self.assertLess(o.t - t0, 600000, f"{len(moves)} moves in 600 s")
            prev = s
            s = o.advance(o.next_slice(s, extra_far=self.SWITCH))
            levels = self.levels(s, *inputs)
            if levels != self.levels(prev, *inputs):
                o.set_inputs(levels)
            if edge_in_slice(o, prev, s):
                moves.append(s["t"])
            if len(o.samples) % 200 == 0 or (moves and moves[-1] == s["t"]):
                o.setobj()
                r_sequence = [v for _, _, i, _, v in o.setobjs if i == 0x6083][1:]
        o.setobj()
        pp = o.setobjs[len(init) + 2 + 4 - 1:]  # from 6060h = 1
        targets = [v for _, _, i, _, v in pp if i == 0x607A]
        self.assertEqual(pp[1][2:], (0x607A, 0, 10000), "z = 2: the first set-point right after 6060h = 1")
        self.assertEqual(targets, [10000 if k % 2 == 0 else -10000 for k in range(len(targets))])
        # each move ends (bit 10, inside the window for 6068h) before the next 607Ah write
        setpoints = [t for t, _, i, _, v in pp if (i, v) == (0x6040, 0x1F)]
        edges = check_move_ends(self, o, setpoints)
        # between two set-points: one target reached, then 6083h and 6084h with the same value
        # (A.5), all before the next 607Ah write
        target_times = [t for t, _, i, _, _ in pp if i == 0x607A]
        acc = [(t, v) for t, _, i, _, v in pp if i == 0x6083]
        dec = [(t, v) for t, _, i, _, v in pp if i == 0x6084]
        self.assertEqual(len(acc), len(dec))
        for k in range(1, len(target_times)):
            lo, hi = target_times[k - 1], target_times[k]
            reached = [e for e in moves if lo < e <= hi]
            self.assertEqual(len(reached), 1, f"targets reached between the set-points at {lo} and {hi}: {reached}")
            ramp_acc = [v for t, v in acc if reached[0] <= t <= hi]
            ramp_dec = [v for t, v in dec if reached[0] <= t <= hi]
            self.assertEqual(len(ramp_acc), 1, f"6083h writes after the target reached at {reached[0]}")
            self.assertEqual(ramp_acc, ramp_dec)
        # A.5: the values 20, 30, …, 500, 490, …, 10, 20, …
        want, r, q = [], 10, 10
        for _ in acc:
            r += q
            if r in (500, 10):
                q = -q
            want.append(r)
        self.assertEqual([v for _, v in acc], want)
        self.assertEqual([v for _, v in dec], want)
        self.assertEqual(want[47:51], [490, 500, 490, 480])
        self.assertEqual(want[96:99], [20, 10, 20])
        # A.6: at least 10 completed moves within 600 s
        self.assertGreaterEqual(edges, 10)
        self.assertLessEqual(moves[9] - t0, 600000)

        # A.6: DigIn1 low, DigIn2 high → 6040h = 0 and Switch on disabled within 10 ms, and it stays so
        inputs = (self.DIGIN2,)
        o.set_inputs(self.levels(s, *inputs))
        t_off = o.t
        while s["sw"] & 0x6F != 0x40:
            self.assertLess(o.t - t_off, 10, "not disabled within 10 ms")
            s = o.advance(1)
        stop = o.setobj()
        self.assertIn((0x6040, 0), writes(stop))
        self.assertTrue(all(t <= t_off + 10 for t, *_ in stop))
        for _ in range(20):
            s = o.advance(100)
            self.assertEqual(s["sw"] & 0x6F, 0x40, "stays disabled")
        self.assertEqual(o.setobj(), [], "no further writes")
        self.assertEqual(o.var("y"), 1)
        print(f"\nExample A: homed at {homed} ms, {edges} moves, the 10th at {moves[9] - t0} ms, "
              f"{len(o.samples)} samples", flush=True)


class ExampleB(unittest.TestCase):
    """AN165 Example B (create a motion profile), faulhaber.md §10 B.1–B.5."""

    def test_example_b(self):
        with Mcemu(*FH, "--clock", "manual") as m:
            o = Observer(m)
            try:
                self.run_example(o)
            finally:
                o.close()

    def run_example(self, o):
        t0 = o.t
        start_program(o, 1, fixture("example_b.bas"))
        # B.1: 6060h = 1, 2310h.01 = .02 = 0, 6040h = 0, then 0x06, 0x0F, Operation enabled
        init = [(0x6060, 1), (0x2310, 0), (0x2310, 0), (0x6040, 0), (0x6040, 0x06), (0x6040, 0x0F)]
        s = o.samples[-1]
        while len(o.setobjs) < len(init) or s["sw"] & 0x6F != 0x27:
            self.assertLess(o.t - t0, 100, o.setobjs)
            s = o.advance(1)
            o.setobj()
        self.assertEqual(writes(o.setobjs[:len(init)]), init)
        self.assertEqual([sub for _, _, _, sub, _ in o.setobjs[1:3]], [0x01, 0x02])
        self.assertEqual(o.read(0x6061), 1)
        self.assertEqual(o.read(0x2310, 1, signed=False), 0)

        # B.2–B.5: run until 3 complete cycles (9 moves), within 120 s of drive time
        cycle = [(0x607A, 0), (0x6068, 500), (0x6040, 0x1F), (0x6040, 0x0F),
                 (0x607A, 40000), (0x6068, 20), (0x6040, 0x1F), (0x6040, 0x0F),
                 (0x607A, 45000), (0x6068, 100), (0x6040, 0x1F), (0x6040, 0x0F)]
        moves = 0
        while moves < 9:
            self.assertLess(o.t - t0, 120000, f"only {moves} moves in 120 s")
            prev = s
            s = o.advance(o.next_slice(s))
            if len(o.setobjs) > len(init) and edge_in_slice(o, prev, s):
                moves += 1
            if len(o.samples) % 200 == 0 or moves == 9 or len(o.setobjs) <= len(init):
                o.setobj()
        o.setobj()
        elapsed = o.t - t0
        sets = o.setobjs[len(init):]
        # B.5 and B.2: the exact write sequence of step 2, three times (and the next cycle as far as
        # it got)
        self.assertGreaterEqual(len(sets), 3 * len(cycle))
        for k, w in enumerate(writes(sets)):
            self.assertEqual(w, cycle[k % len(cycle)], f"write {k} after the start")
        # B.2: 0x0F once bit 10 has dropped: the drop is a notification in the ms of the 0x1F write
        # (B.3: inside the write); the 0x0F write comes at the same time or later
        setpoints = [t for t, _, index, _, value in sets if (index, value) == (0x6040, 0x1F)]
        for k, t in enumerate(setpoints):
            self.assertTrue(any(nt == t and not sw & 0x0400 for nt, sw in o.notes),
                            f"bit 10 did not drop in the ms of the 0x1F write at {t} ms")
        for k in range(len(sets) - 1):
            if writes(sets[k:k + 1]) == [(0x6040, 0x1F)]:
                self.assertEqual(writes(sets[k + 1:k + 2]), [(0x6040, 0x0F)])
                self.assertGreaterEqual(sets[k + 1][0], sets[k][0])
        # B.3: the first set-point equals the actual position 0: bit 10 drops inside the 0x1F write
        # and rises 500 ms later
        first = setpoints[0]
        self.assertEqual(writes(sets[:1]), [(0x607A, 0)])
        self.assertEqual([x["pos"] for x in o.samples if x["t"] < first][-1], 0)
        rises = [t for t, sw in o.notes if t > first and sw & 0x0400]
        self.assertIn(rises[0] - first, (500, 501), f"bit 10 rose {rises[0] - first} ms after the 0x1F write")
        # B.4: every rising edge inside the window, after the window time; B.5: 9 moves in 120 s
        edges = check_move_ends(self, o, setpoints)
        self.assertGreaterEqual(edges, 9)
        self.assertLessEqual(elapsed, 120000)
        print(f"\nExample B: {edges} moves in {elapsed} ms of drive time, {len(o.samples)} samples", flush=True)


def programs(h):
    return h.json("GET", "/api/v1/faulhaber/programs")


def slot(h, n):
    return programs(h)["programs"][n - 1]


class Manual:
    """An FAULHABER drive under --clock manual with an HTTP connection and a protocol client."""

    def __init__(self, m):
        self.m = m
        self.h = Http(m.ports["http"])
        self.c = fc.open_tcp(m.ports["faulhaber"])

    def advance(self, ms):
        return self.h.json("POST", "/api/v1/clock/advance", {"ms": ms})["timeMs"]

    def upload(self, n, text):
        return self.h.json("PUT", f"/api/v1/faulhaber/programs/{n}", text.encode(), content_type="text/plain")

    def start(self, n, expect=200):
        return self.h.json("POST", f"/api/v1/faulhaber/programs/{n}/start", {}, expect=expect)

    def var(self, name):
        return self.c.read_int(0x3005, VAR[name])

    def close(self):
        self.c.close()
        self.h.close()


class ProgramsAndState(unittest.TestCase):
    def test_save_load_and_programs_survive_a_restart(self):
        tmp = tempfile.TemporaryDirectory(prefix="mcemu-basic-")
        self.addCleanup(tmp.cleanup)
        state = os.path.join(tmp.name, "state")
        saver = "' SAVE keeps a and b\r\na = 11\r\nb = -22\r\nSAVE a, b\r\nc = 5\r\n"
        loader = "LOAD a, b\nd = a + b\n"
        broken = "a = 1\nGOTO Nowhere\n"
        with Mcemu(*FH, "--clock", "manual", state_dir=state) as m:
            d = Manual(m)
            try:
                self.assertEqual(d.upload(1, saver)["state"], "loaded")
                self.assertEqual(d.upload(2, loader)["state"], "loaded")
                bad = d.upload(3, broken)  # stored and answered 200 with its error (faulhaber.md §9.1)
                self.assertEqual((bad["state"], bad["line"]), ("error", 2))
                self.assertIn("nowhere", bad["message"].lower())
                self.assertEqual(d.start(3, expect=409)["state"], "error")
                self.assertEqual(d.start(5, expect=409)["state"], "empty")
                status, _ = d.h.request("PUT", "/api/v1/faulhaber/programs/4", b"a = 1\n" * 683, "text/plain")
                self.assertEqual(status, 413, "4098 bytes")
                self.assertEqual(slot(d.h, 4)["state"], "empty", "nothing stored")
                d.start(1)
                d.advance(5)
                self.assertEqual((d.var("a"), d.var("b"), d.var("c")), (11, -22, 5))
                after = programs(d.h)
                self.assertEqual(after["running"], 0, "the end of the text stops the program")
                self.assertNotIn(after["programs"][0]["state"], ("running", "error"))
                self.assertEqual(after["saves"], 1)
            finally:
                d.close()
        with open(os.path.join(state, "faulhaber", "variables.json")) as f:
            self.assertEqual(json.load(f), {"a": 11, "b": -22})
        with Mcemu(*FH, "--clock", "manual", state_dir=state) as m:
            d = Manual(m)
            try:
                listing = programs(d.h)["programs"]
                self.assertEqual([p["state"] for p in listing[:4]], ["loaded", "loaded", "error", "empty"])
                self.assertEqual(listing[0]["bytes"], len(saver))
                self.assertEqual(listing[2]["line"], 2)
                self.assertEqual(d.h.json("GET", "/api/v1/faulhaber/programs/1")["source"], saver)
                self.assertEqual(d.h.json("GET", "/api/v1/faulhaber/programs/2")["source"], loader)
                self.assertEqual((d.var("a"), d.var("b"), d.var("d")), (0, 0, 0), "variables are 0 after power on")
                d.start(2)
                d.advance(5)
                self.assertEqual((d.var("a"), d.var("b"), d.var("d")), (11, -22, -11))
            finally:
                d.close()

    def test_autostart_after_power_cycle_reset_node_and_restart(self):
        tmp = tempfile.TemporaryDirectory(prefix="mcemu-basic-")
        self.addCleanup(tmp.cleanup)
        state = os.path.join(tmp.name, "state")
        counter = "f = f + 1\n:Idle\nGOTO Idle\n"
        with Mcemu(*FH, "--clock", "manual", state_dir=state) as m:
            d = Manual(m)
            try:
                d.upload(4, counter)
                self.assertEqual(d.h.json("PUT", "/api/v1/faulhaber/autostart", {"program": 4})["autostart"], 4)
                self.assertEqual(programs(d.h)["running"], 0, "autostart acts at power on, not at once")
                d.h.json("POST", "/api/v1/power-cycle", {})
                d.advance(5)
                self.assertEqual(programs(d.h)["running"], 4)
                self.assertEqual(slot(d.h, 4)["state"], "running")
                self.assertEqual(d.var("f"), 1)
                d.c.send(bytes.fromhex("53 04 01 00 50 45"))  # reset node telegram
                d.c.wait_notification(lambda f: f.command == fc.BOOT, what="boot message")
                d.advance(5)
                self.assertEqual((programs(d.h)["running"], d.var("f")), (4, 1), "restarted, variables back to 0")
                d.h.json("POST", "/api/v1/faulhaber/stop", {})
                self.assertEqual(programs(d.h)["running"], 0)
                self.assertEqual(slot(d.h, 4)["state"], "stopped")
            finally:
                d.close()
        with Mcemu(*FH, "--clock", "manual", state_dir=state) as m:  # autostart kept in the state dir
            d = Manual(m)
            try:
                d.advance(5)
                self.assertEqual((programs(d.h)["autostart"], programs(d.h)["running"], d.var("f")), (4, 4, 1))
            finally:
                d.close()

    def test_protocol_write_of_0x3005_seen_by_the_next_statement(self):
        cfg = config_file({"faulhaber": {"basic_statements_per_ms": 1}})
        self.addCleanup(os.unlink, cfg)
        with Mcemu(*FH, "--clock", "manual", "--config", cfg) as m:
            d = Manual(m)
            try:
                d.upload(1, "a = i\nb = i\nc = i\nd = i\n:Idle\nGOTO Idle\n")
                d.c.sdo_write(0x3005, 0x09, 5, 4)  # i = 5 before the start (AN165's master pattern)
                d.start(1)
                d.advance(2)  # one statement per ms: a = i, b = i
                self.assertEqual((d.var("a"), d.var("b"), d.var("c")), (5, 5, 0))
                self.assertEqual(slot(d.h, 1).get("runningLine"), 3)
                d.c.sdo_write(0x3005, 0x09, 7, 4)  # between two statements
                d.advance(1)
                self.assertEqual((d.var("b"), d.var("c"), d.var("d")), (5, 7, 0))
                d.advance(1)
                self.assertEqual(d.var("d"), 7)
                # and a program's assignment is what the master reads next
                self.assertEqual(d.c.read_int(0x3005, 0x04), 7)
            finally:
                d.close()


class RunawayPrograms(unittest.TestCase):
    """A program that loops forever, divides by zero or recurses without end ends in a clear state
    and never stalls the other drive of the process or the HTTP answers (real clock)."""

    def test_runaway_programs(self):
        with Mcemu(*FH, "--drives", "2") as m:
            wait_for(lambda: len(m.drives) == 2 and all("faulhaber" in d for d in m.drives.values()), what="drives")
            h1 = Http(m.drives[1]["http"][1], host=m.drives[1]["http"][0])
            c1 = fc.open_tcp(m.drives[1]["faulhaber"][1], host=m.drives[1]["faulhaber"][0])
            c2 = fc.open_tcp(m.drives[2]["faulhaber"][1], host=m.drives[2]["faulhaber"][0])
            try:
                def put(n, text):
                    return h1.json("PUT", f"/api/v1/faulhaber/programs/{n}", text.encode(), content_type="text/plain")

                put(1, ":Spin\na = a + 1\nGOTO Spin\n")
                put(2, "a = 1\nb = 0\nc = a / b\n")
                put(3, "' endless recursion\n:Deeper\nGOSUB Deeper\n")
                put(4, "FOR k = 1 TO 2 STEP 0\nNEXT k\n")
                h1.json("POST", "/api/v1/faulhaber/programs/2/start", {})
                wait_for(lambda: h1.json("GET", "/api/v1/faulhaber/programs")["programs"][1]["state"] == "error",
                         what="division by zero")
                p2 = h1.json("GET", "/api/v1/faulhaber/programs")["programs"][1]
                self.assertEqual(p2["line"], 3)
                self.assertIn("zero", p2["message"])
                h1.json("POST", "/api/v1/faulhaber/programs/3/start", {})
                wait_for(lambda: h1.json("GET", "/api/v1/faulhaber/programs")["programs"][2]["state"] == "error",
                         what="GOSUB depth")
                p3 = h1.json("GET", "/api/v1/faulhaber/programs")["programs"][2]
                self.assertEqual(p3["line"], 3)
                self.assertIn("16", p3["message"])
                for n in (4, 1):  # STEP 0 forever, then the spinning assignment loop
                    h1.json("POST", f"/api/v1/faulhaber/programs/{n}/start", {})
                    self.assertEqual(h1.json("GET", "/api/v1/faulhaber/programs")["running"], n)
                    a0 = c1.read_int(0x3005, 1)
                    wait_for(lambda: c1.read_int(0x3005, 1) > a0 + 1000 or n == 4, what="spinning")
                    # meanwhile drive 2 moves and answers; drive 1's HTTP and protocol answer
                    c2.sdo_write(0x6060, 0, 1, 1)
                    c2.controlword(0x06)
                    c2.controlword(0x0F)
                    target = c2.position() + 20000
                    c2.sdo_write(0x607A, 0, target, 4)
                    c2.controlword(0x1F)
                    c2.controlword(0x0F)
                    worst = 0.0
                    deadline = time.monotonic() + 30
                    while not (c2.statusword() & 0x0400 and c2.position() == target):
                        self.assertLess(time.monotonic(), deadline, "drive 2 never reached its target")
                        t = time.monotonic()
                        self.assertEqual(h1.json("GET", "/api/v1/info")["model"], "FH_MC5005")
                        c1.statusword()
                        worst = max(worst, time.monotonic() - t)
                    self.assertLess(worst, 5.0, "an HTTP or protocol answer took seconds")
                    self.assertEqual(h1.json("GET", "/api/v1/faulhaber/programs")["running"], n, "still running")
                    stopped = h1.json("POST", "/api/v1/faulhaber/stop", {})
                    self.assertEqual(stopped["running"], 0)
                    self.assertEqual(stopped["programs"][n - 1]["state"], "stopped")
            finally:
                c1.close()
                c2.close()
                h1.close()


if __name__ == "__main__":
    unittest.main()
